//! Sparse matrices (faer's compressed columns): construction from triplets, the union
//! `a X + b Y`, their stored entries, diagonal and bandwidth.

use crate::error::{Error, Result};
use faer::sparse::{SparseColMat, Triplet};

/// Sparse matrix in compressed-column form (faer).
pub type SpMat = SparseColMat<usize, f64>;

/// Accumulates `(row, col, value)` entries; duplicates are summed on [`TripletBuilder::build`].
#[derive(Debug, Clone, Default)]
pub struct TripletBuilder {
    nrows: usize,
    ncols: usize,
    entries: Vec<Triplet<usize, usize, f64>>,
}

impl TripletBuilder {
    /// An empty `nrows × ncols` matrix.
    pub fn new(nrows: usize, ncols: usize) -> Self {
        Self {
            nrows,
            ncols,
            entries: Vec::new(),
        }
    }

    /// Adds `value` at `(row, col)` (summed with previous entries there).
    pub fn add(&mut self, row: usize, col: usize, value: f64) {
        debug_assert!(row < self.nrows && col < self.ncols);
        self.entries.push(Triplet::new(row, col, value));
    }

    /// Adds `scale · m` with its top-left corner at `(row0, col0)`.
    pub fn add_scaled(&mut self, row0: usize, col0: usize, scale: f64, m: &SpMat) {
        for (i, j, v) in triplets(m) {
            self.add(row0 + i, col0 + j, scale * v);
        }
    }

    /// The assembled matrix: entries bucketed by column (counting sort), then each column
    /// sorted by row (stable: duplicates are summed in insertion order) and merged.
    pub fn build(&self) -> Result<SpMat> {
        let (n, m) = (self.nrows, self.ncols);
        if let Some(t) = self.entries.iter().find(|t| t.row >= n || t.col >= m) {
            return Err(Error::Internal(format!(
                "{n}x{m} assembly: entry ({}, {}) out of bounds",
                t.row, t.col
            )));
        }
        let mut start = vec![0usize; m + 1];
        for t in &self.entries {
            start[t.col + 1] += 1;
        }
        for j in 0..m {
            start[j + 1] += start[j];
        }
        let mut next = start.clone();
        let mut bucket = vec![(0usize, 0.0f64); self.entries.len()];
        for t in &self.entries {
            bucket[next[t.col]] = (t.row, t.val);
            next[t.col] += 1;
        }
        let mut col_ptr = Vec::with_capacity(m + 1);
        let mut row_idx = Vec::with_capacity(bucket.len());
        let mut val = Vec::with_capacity(bucket.len());
        col_ptr.push(0);
        for j in 0..m {
            let col = &mut bucket[start[j]..start[j + 1]];
            col.sort_by_key(|e| e.0);
            for &(i, v) in col.iter() {
                if row_idx.len() > col_ptr[j] && row_idx.last() == Some(&i) {
                    if let Some(last) = val.last_mut() {
                        *last += v;
                    }
                } else {
                    row_idx.push(i);
                    val.push(v);
                }
            }
            col_ptr.push(row_idx.len());
        }
        let symbolic =
            faer::sparse::SymbolicSparseColMat::new_checked(n, m, col_ptr, None, row_idx);
        Ok(SpMat::new(symbolic, val))
    }
}

/// The rows of a sparse matrix as `(column, value)` lists (short rows, e.g. contact rows).
pub fn rows(m: &SpMat) -> Vec<Vec<(usize, f64)>> {
    let mut rows = vec![Vec::new(); m.nrows()];
    for (i, j, v) in triplets(m) {
        rows[i].push((j, v));
    }
    rows
}

/// Stored entries `(row, col, value)` of a sparse matrix.
pub fn triplets(m: &SpMat) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
    let m = m.as_ref();
    (0..m.ncols()).flat_map(move |j| {
        m.row_idx_of_col_raw(j)
            .iter()
            .zip(m.val_of_col(j))
            .map(move |(&i, &v)| (i, j, v))
    })
}

/// Compressed-column arrays `(col_ptr, row_idx, values)` of `a`, whose columns are contiguous
/// (faer matrices built from triplets are).
pub(super) fn csc(a: &SpMat) -> (&[usize], &[usize], &[f64]) {
    let a = a.as_ref();
    debug_assert!(a.symbolic().col_nnz().is_none());
    (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val())
}

/// The diagonal of a sparse matrix (compressed columns, rows sorted, as every matrix here is
/// built), by a search in each column, in parallel.
pub fn diagonal(a: &SpMat) -> Vec<f64> {
    use rayon::prelude::*;
    let (cp, ri, v) = csc(a);
    let mut d = vec![0.0; a.nrows()];
    // Column j's rows are sorted: its entries on row j are one run.
    let n = a.ncols().min(a.nrows());
    d[..n].par_iter_mut().enumerate().for_each(|(j, d)| {
        let rows = &ri[cp[j]..cp[j + 1]];
        let first = rows.partition_point(|&i| i < j);
        for k in (first..rows.len()).take_while(|&k| rows[k] == j) {
            *d += v[cp[j] + k];
        }
    });
    d
}

/// `A = a · X + b · Y` for two sparse matrices of the same shape (union of the patterns), by a
/// merge of their sorted columns (no triplet sort): each column's entries counted, then the
/// columns merged into their place, both in parallel by chunks of columns.
pub fn lin_comb(a: f64, x: &SpMat, b: f64, y: &SpMat) -> Result<SpMat> {
    use rayon::prelude::*;
    let (n, m) = (x.nrows(), x.ncols());
    if (y.nrows(), y.ncols()) != (n, m) {
        return Err(Error::Internal(format!(
            "a · X + b · Y of a {n}x{m} and a {}x{} matrix",
            y.nrows(),
            y.ncols()
        )));
    }
    let ((xp, xi, xv), (yp, yi, yv)) = (csc(x), csc(y));
    // Column j of the union, `emit(row, a x + b y)` in row order.
    let merge = |j: usize, emit: &mut dyn FnMut(usize, f64)| {
        let (mut p, mut q) = (xp[j], yp[j]);
        while p < xp[j + 1] || q < yp[j + 1] {
            let rx = if p < xp[j + 1] { xi[p] } else { usize::MAX };
            let ry = if q < yp[j + 1] { yi[q] } else { usize::MAX };
            let r = rx.min(ry);
            let mut v = 0.0;
            if rx == r {
                v += a * xv[p];
                p += 1;
            }
            if ry == r {
                v += b * yv[q];
                q += 1;
            }
            emit(r, v);
        }
    };
    let counts: Vec<usize> = (0..m)
        .into_par_iter()
        .map(|j| {
            let mut count = 0;
            merge(j, &mut |_, _| count += 1);
            count
        })
        .collect();
    let mut col_ptr = Vec::with_capacity(m + 1);
    col_ptr.push(0);
    for c in counts {
        col_ptr.push(col_ptr[col_ptr.len() - 1] + c);
    }
    let (mut row_idx, mut val) = (vec![0; col_ptr[m]], vec![0.0; col_ptr[m]]);
    let cuts = column_cuts(m, MERGE_CHUNK);
    let rows = split_columns(&cuts, |j| col_ptr[j], &mut row_idx);
    let vals = split_columns(&cuts, |j| col_ptr[j], &mut val);
    (cuts.par_windows(2).zip(rows).zip(vals)).for_each(|((w, rows), vals)| {
        let mut k = 0;
        for j in w[0]..w[1] {
            merge(j, &mut |r, v| {
                (rows[k], vals[k]) = (r, v);
                k += 1;
            });
        }
    });
    let symbolic = faer::sparse::SymbolicSparseColMat::new_checked(n, m, col_ptr, None, row_idx);
    Ok(SpMat::new(symbolic, val))
}

/// Columns merged by one task of [`lin_comb`].
const MERGE_CHUNK: usize = 4096;

/// The boundaries of consecutive ranges of `chunk` columns out of `m`: `0, chunk, …, m`.
pub(crate) fn column_cuts(m: usize, chunk: usize) -> Vec<usize> {
    (0..m).step_by(chunk.max(1)).chain([m]).collect()
}

/// The boundaries of `parts` ranges of columns holding about as many entries each (some may be
/// empty), from the columns' starts `ptr`: `0, …, m`.
pub(crate) fn balanced_cuts(ptr: &[usize], parts: usize) -> Vec<usize> {
    let (total, m) = (ptr[ptr.len() - 1], ptr.len() - 1);
    let cut = |p: usize| ptr.partition_point(|&q| q < total * p / parts).min(m);
    (0..parts).map(cut).chain([m]).collect()
}

/// `data` (from column `cuts[0]`) cut at the increasing boundaries `cuts` of ranges of columns,
/// column c starting at `offset(c)`: one disjoint slice per range, to fill the columns in
/// parallel. What follows the last range's columns is left out (e.g. a padding value).
pub(crate) fn split_columns<'a, T>(
    cuts: &[usize],
    offset: impl Fn(usize) -> usize,
    mut data: &'a mut [T],
) -> Vec<&'a mut [T]> {
    let mut parts = Vec::with_capacity(cuts.len().saturating_sub(1));
    for w in cuts.windows(2) {
        debug_assert!(offset(w[0]) <= offset(w[1]) && offset(w[1]) - offset(w[0]) <= data.len());
        let (part, rest) = std::mem::take(&mut data).split_at_mut(offset(w[1]) - offset(w[0]));
        data = rest;
        parts.push(part);
    }
    parts
}

/// True when `a` has bandwidth at most [`NARROW_BAND`] (1D meshes).
pub fn is_narrow_band(a: &SpMat) -> bool {
    bandwidth(a) <= NARROW_BAND
}

/// Largest bandwidth kept in the natural order by [`Factor::cholesky`].
pub(super) const NARROW_BAND: usize = 4;

/// `max |i − j|` over the stored entries.
pub(super) fn bandwidth(a: &SpMat) -> usize {
    triplets(a)
        .map(|(i, j, _)| i.abs_diff(j))
        .max()
        .unwrap_or(0)
}

/// Dense copy (tests and small diagnostics only).
pub fn to_dense(a: &SpMat) -> nalgebra::DMatrix<f64> {
    let mut d = nalgebra::DMatrix::zeros(a.nrows(), a.ncols());
    for (i, j, v) in triplets(a) {
        d[(i, j)] += v;
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::testing::block_matrix;

    #[test]
    fn cuts_cover_every_column_once_even_when_empty() {
        assert_eq!(column_cuts(0, 5), vec![0]);
        assert_eq!(column_cuts(10, 5), vec![0, 5, 10]);
        assert_eq!(column_cuts(11, 5), vec![0, 5, 10, 11]);
        // No entry at all, and entries only in the first column.
        assert_eq!(balanced_cuts(&[0, 0, 0], 2), vec![0, 0, 2]);
        assert_eq!(balanced_cuts(&[0, 4, 4, 4], 2), vec![0, 1, 3]);
        assert_eq!(balanced_cuts(&[0, 2, 4, 6, 8], 4), vec![0, 1, 2, 3, 4]);
        // The slices follow the columns' starts; what follows the last column is left out.
        let ptr = [0, 2, 2, 5];
        let mut data = [1, 1, 3, 3, 3, 9];
        let parts = split_columns(&[0, 1, 3], |c| ptr[c], &mut data);
        assert_eq!(parts, [&mut [1, 1][..], &mut [3, 3, 3][..]]);
        assert!(split_columns(&[0], |c| ptr[c], &mut data).is_empty());
    }

    /// The parallel diagonal and `a X + b Y` against their definitions, entry by entry, on a
    /// matrix of 3 × 3 blocks and a rectangular one.
    #[test]
    fn diagonal_and_lin_comb_match_their_definitions() {
        let x = block_matrix(9, 3);
        let mut t = TripletBuilder::new(27, 27);
        for i in 0..27 {
            t.add(i, (i * 5) % 27, 0.1 * i as f64);
        }
        let y = t.build().unwrap();
        let sum = lin_comb(2.0, &x, -0.5, &y).unwrap();
        let (dx, dy) = (to_dense(&x), to_dense(&y));
        let ds = to_dense(&sum);
        for i in 0..27 {
            for j in 0..27 {
                assert_eq!(ds[(i, j)], 2.0 * dx[(i, j)] + -0.5 * dy[(i, j)]);
            }
            assert_eq!(diagonal(&sum)[i], ds[(i, i)]);
        }
        let mut t = TripletBuilder::new(2, 3);
        t.add(1, 1, 5.0);
        t.add(0, 2, 7.0);
        assert_eq!(diagonal(&t.build().unwrap()), vec![0.0, 5.0]);
    }
}
