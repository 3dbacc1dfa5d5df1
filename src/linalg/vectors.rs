//! Vector kernels: inner products (sequential, unordered, and chunked in a fixed order on the
//! rayon pool) and the `a x + b y` updates of the time schemes.

/// Euclidean inner product summed in four interleaved partial sums (not bit-identical to
/// [`dot`]; a sequential sum is bound by the latency of one addition per term).
pub fn dot_unordered(x: &[f64], y: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let (xc, yc) = (x.chunks_exact(4), y.chunks_exact(4));
    let tail = dot(xc.remainder(), yc.remainder());
    for (a, b) in xc.zip(yc) {
        for k in 0..4 {
            acc[k] += a[k] * b[k];
        }
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// `Σ_j v_j u_j` over a sparse row `(j, v_j)`.
pub fn row_dot(row: &[(usize, f64)], u: &[f64]) -> f64 {
    row.iter().map(|&(j, v)| v * u[j]).sum()
}

/// Euclidean inner product.
pub fn dot(x: &[f64], y: &[f64]) -> f64 {
    x.iter().zip(y).map(|(a, b)| a * b).sum()
}

/// Entries per chunk of the vector passes of CG: each chunk forms its own sums and the chunk
/// sums are added in order, so that the result does not depend on the number of threads. A
/// multiple of 2 and 3, so that a chunk holds whole nodes of a 2D or 3D vector field.
pub const PASS_CHUNK: usize = 4098;

/// Chunk sums added in order.
fn sum_in_order(chunks: impl rayon::iter::IndexedParallelIterator<Item = f64>) -> f64 {
    let mut sums = Vec::new();
    chunks.collect_into_vec(&mut sums);
    sums.iter().sum()
}

/// `y_i ← g(i, y_i)` where `free_i`, 0 elsewhere, for every i, returning `Σ_i x_i y_i` (chunks of
/// [`PASS_CHUNK`] on the rayon pool).
pub fn masked_dot(
    y: &mut [f64],
    x: &[f64],
    free: &[bool],
    g: impl Fn(usize, f64) -> f64 + Sync,
) -> f64 {
    use rayon::prelude::*;
    let chunks = y.par_chunks_mut(PASS_CHUNK).zip(x.par_chunks(PASS_CHUNK));
    sum_in_order(
        chunks
            .zip(free.par_chunks(PASS_CHUNK))
            .enumerate()
            .map(|(c, ((y, x), free))| {
                for (k, (yi, &f)) in y.iter_mut().zip(free).enumerate() {
                    *yi = if f { g(c * PASS_CHUNK + k, *yi) } else { 0.0 };
                }
                dot_unordered(x, y)
            }),
    )
}

/// `out = a x + b y`.
pub fn combine(out: &mut [f64], (a, x): (f64, &[f64]), (b, y): (f64, &[f64])) {
    for ((o, xi), yi) in out.iter_mut().zip(x).zip(y) {
        *o = a * xi + b * yi;
    }
}

/// `y = a y + b x`.
pub fn scale_add(y: &mut [f64], a: f64, b: f64, x: &[f64]) {
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi = a * *yi + b * xi;
    }
}

/// `y += alpha x`.
pub fn axpy(y: &mut [f64], alpha: f64, x: &[f64]) {
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi += alpha * xi;
    }
}
