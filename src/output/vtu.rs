//! Field output for ParaView: one VTK XML unstructured grid (`.vtu`, raw binary encoded in
//! base64, written with vtkio) per written step, and a `.pvd` collection listing the files with
//! their times (ParaView opens the `.pvd` as one time series).
//!
//! Point data, 3 components with z = 0 in 2D: `displacement`, `velocity`; scalar
//! `contact_pressure` = λ_r / |Γ_C|_r on the vertices of Γ_C (≥ 0 in compression), 0 elsewhere.
//! Cell data: `von_mises`, the von Mises stress at the cell centroid (plane strain in 2D).
//! Points are the reference (undeformed) positions: ParaView's *Warp By Vector* on
//! `displacement` draws the deformed body.
//!
//! **Several bodies** (`two_discs`, `two_spheres`): one grid per sample holding every body, its
//! points and cells body after body, with the cell array `body` (1 the slave, 2 the master):
//! one file and one pipeline per time step as for one body (*Warp By Vector* moves both
//! bodies, *Threshold* on `body` shows one). `contact_pressure` is on both sides of the
//! interface: the row's `λ_r / |Γ_C|_r` at the slave's vertex, and the reaction `Σ_r N_k λ_r`
//! spread on the master face's vertices k by its shape functions, over the master vertex's
//! tributary area ([`crate::fem::bodies::Bodies::vertex_shares`]); the two integrate to the
//! same total force. P2/Q2 cells are VTK's quadratic cells (quadratic
//! triangle 22, biquadratic quad 28, quadratic tetra 24, triquadratic hexahedron 29), their
//! nodes permuted into VTK's order by reference coordinates ([`vtk_order`]).

use crate::element::reference::{RefElement, Shape};
use crate::error::{Error, Result};
use crate::fem::discretisation::Discretisation;
use std::path::{Path, PathBuf};
use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataSet, UnstructuredGridPiece, Version,
    VertexNumbers, Vtk,
};

/// For degree 2, VTK's further nodes after the vertices: each the centroid of a group of
/// vertices (indices into [`RefElement::cyclic_vertices`], VTK's vertex order).
fn vtk_groups(el: &RefElement) -> &'static [&'static [usize]] {
    match (el.shape, el.dim) {
        (Shape::Simplex, 2) => &[&[0, 1], &[1, 2], &[2, 0]],
        (Shape::Tensor, 2) => &[&[0, 1], &[1, 2], &[2, 3], &[3, 0], &[0, 1, 2, 3]],
        (Shape::Simplex, _) => &[&[0, 1], &[1, 2], &[2, 0], &[0, 3], &[1, 3], &[2, 3]],
        (Shape::Tensor, _) => &[
            &[0, 1],
            &[1, 2],
            &[2, 3],
            &[3, 0],
            &[4, 5],
            &[5, 6],
            &[6, 7],
            &[7, 4],
            &[0, 4],
            &[1, 5],
            &[2, 6],
            &[3, 7],
            &[0, 3, 7, 4],
            &[1, 2, 6, 5],
            &[0, 1, 5, 4],
            &[3, 2, 6, 7],
            &[0, 1, 2, 3],
            &[4, 5, 6, 7],
            &[0, 1, 2, 3, 4, 5, 6, 7],
        ],
    }
}

/// The VTK cell type of `el` and, for each VTK local node, the local node of `el`: the vertices
/// in their conventional order, then (degree 2) the node at the centroid of each VTK group.
pub fn vtk_order(el: &RefElement) -> (CellType, Vec<usize>) {
    let mut order = el.cyclic_vertices();
    if el.degree == 2 {
        let corners = order.clone();
        order.extend(vtk_groups(el).iter().map(|g| {
            let x: [f64; 3] = std::array::from_fn(|k| {
                g.iter().map(|&i| el.node(corners[i])[k]).sum::<f64>() / g.len() as f64
            });
            (0..el.n_nodes())
                .find(|&a| {
                    el.node(a)
                        .iter()
                        .zip(&x)
                        .all(|(p, q)| (p - q).abs() < 1e-12)
                })
                .expect("every VTK node of a Lagrange cell of degree ≤ 2 is one of its nodes")
        }));
    }
    let cell_type = match (el.shape, el.dim, el.degree) {
        (Shape::Simplex, 2, 1) => CellType::Triangle,
        (Shape::Tensor, 2, 1) => CellType::Quad,
        (Shape::Simplex, _, 1) => CellType::Tetra,
        (Shape::Tensor, _, 1) => CellType::Hexahedron,
        (Shape::Simplex, 2, _) => CellType::QuadraticTriangle,
        (Shape::Tensor, 2, _) => CellType::BiquadraticQuad,
        (Shape::Simplex, _, _) => CellType::QuadraticTetra,
        (Shape::Tensor, _, _) => CellType::TriquadraticHexahedron,
    };
    (cell_type, order)
}

/// The name of sample `index`'s file in the series `stem`: `<stem>_<index:06>.vtu`.
fn series_name(stem: &str, index: usize) -> String {
    format!("{stem}_{index:06}.vtu")
}

/// The sample index of the file `name` when [`VtuSeries`] names a file of the series `stem`
/// so, exactly (`block2d_000012.vtu`; not `block2d_12.vtu`, `block2d_0000012.vtu` or
/// `block2d_+00012.vtu`): the files a run of the case may write, replace or remove in its
/// `--vtu` directory.
pub fn series_index(stem: &str, name: &str) -> Option<usize> {
    let digits = name
        .strip_prefix(stem)?
        .strip_prefix('_')?
        .strip_suffix(".vtu")?;
    let index = digits
        .bytes()
        .all(|b| b.is_ascii_digit())
        .then(|| digits.parse().ok())??;
    (series_name(stem, index) == name).then_some(index)
}

/// Fields of a body (or of several bodies, one grid) written every `every` samples into `dir`
/// as `<stem>_<index>.vtu`, listed in `<stem>.pvd` (rewritten after each file, so that it is
/// valid if the run stops). The files of the series `<stem>` in `dir` that the collection does
/// not list (an earlier run's, at other samples) are removed once the first file is written,
/// so that the directory holds one run's series whenever the run stops: ParaView groups the
/// files of a directory by their name pattern, and would mix two runs.
pub struct VtuSeries<'a> {
    parts: Vec<&'a Discretisation>,
    dir: PathBuf,
    stem: String,
    every: usize,
    cells: Cells,
    points: Vec<f64>,
    written: Vec<(f64, String)>,
}

/// The state written at one sample.
pub struct Fields<'s> {
    /// Time.
    pub t: f64,
    /// Displacement U (dof layout of the discretisation).
    pub u: &'s [f64],
    /// Velocity, in V_h or in H_h (see [`Discretisation::nodal_velocity`]).
    pub v: &'s [f64],
    /// Nodal contact forces λ on the Γ_C vertices.
    pub lambda: &'s [f64],
}

/// `d`-component nodal values padded to 3 components.
fn padded(values: &[f64], d: usize) -> Vec<f64> {
    values
        .chunks(d)
        .flat_map(|c| (0..3).map(move |k| c.get(k).copied().unwrap_or(0.0)))
        .collect()
}

impl<'a> VtuSeries<'a> {
    /// Creates `dir`; `every ≥ 1` (checked by the caller's argument validation, refused here too).
    pub fn new(fem: &'a Discretisation, dir: &Path, stem: &str, every: usize) -> Result<Self> {
        Self::of_bodies(vec![fem], dir, stem, every)
    }

    /// As [`VtuSeries::new`] for several bodies in one grid: their points and cells one after
    /// the other, with the cell array `body` (1, 2, …) when there are several.
    pub fn of_bodies(
        parts: Vec<&'a Discretisation>,
        dir: &Path,
        stem: &str,
        every: usize,
    ) -> Result<Self> {
        if every == 0 {
            return Err(Error::invalid("vtu-every", every, "must be ≥ 1"));
        }
        if dir.exists() && !dir.is_dir() {
            return Err(Error::Vtk {
                path: dir.to_path_buf(),
                message: "exists and is not a directory".into(),
            });
        }
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        let (mut connectivity, mut offsets, mut types) = (Vec::new(), Vec::new(), Vec::new());
        let mut node0 = 0;
        for fem in &parts {
            let (cell_type, order) = vtk_order(&fem.mesh.element);
            for cell in &fem.mesh.connectivity {
                connectivity.extend(order.iter().map(|&a| (node0 + cell[a]) as u64));
                offsets.push(connectivity.len() as u64);
                types.push(cell_type);
            }
            node0 += fem.mesh.nodes.len();
        }
        Ok(Self {
            points: parts
                .iter()
                .flat_map(|fem| fem.mesh.nodes.iter().flatten().copied())
                .collect(),
            parts,
            dir: dir.to_path_buf(),
            stem: stem.to_string(),
            every,
            cells: Cells {
                cell_verts: VertexNumbers::XML {
                    connectivity,
                    offsets,
                },
                types,
            },
            written: Vec::new(),
        })
    }

    /// Writes sample number `index` of the run when `index` is a multiple of `every`.
    pub fn sample(&mut self, index: usize, s: &Fields<'_>) -> Result<()> {
        self.sample_bodies(index, std::slice::from_ref(s))
    }

    /// As [`VtuSeries::sample`] with each body's fields (in the order of the bodies).
    pub fn sample_bodies(&mut self, index: usize, s: &[Fields<'_>]) -> Result<()> {
        if !index.is_multiple_of(self.every) {
            return Ok(());
        }
        if s.len() != self.parts.len() {
            return Err(Error::Internal(format!(
                "fields of {} bodies for a grid of {}",
                s.len(),
                self.parts.len()
            )));
        }
        let name = series_name(&self.stem, index);
        let path = self.dir.join(&name);
        let (mut u, mut v, mut p, mut mises, mut body) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for (b, (fem, f)) in self.parts.iter().zip(s).enumerate() {
            let d = fem.dim();
            u.extend(padded(f.u, d));
            v.extend(padded(&fem.nodal_velocity(f.v)?, d));
            p.extend(fem.contact_pressure(f.lambda));
            let von_mises = fem.von_mises(f.u);
            body.extend(std::iter::repeat_n((b + 1) as f64, von_mises.len()));
            mises.extend(von_mises);
        }
        let point = vec![
            Attribute::vectors("displacement").with_data(u),
            Attribute::vectors("velocity").with_data(v),
            Attribute::scalars("contact_pressure", 1).with_data(p),
        ];
        let mut cell = vec![Attribute::scalars("von_mises", 1).with_data(mises)];
        if self.parts.len() > 1 {
            cell.push(Attribute::scalars("body", 1).with_data(body));
        }
        let t = s[0].t;
        let vtk = Vtk {
            version: Version::new_xml(1, 0),
            byte_order: ByteOrder::LittleEndian,
            title: format!("{} t = {t:.6e}", self.stem),
            file_path: None,
            data: DataSet::inline(UnstructuredGridPiece {
                points: self.points.clone().into(),
                cells: self.cells.clone(),
                data: Attributes { point, cell },
            }),
        };
        super::atomic::write_with(&path, |tmp| {
            vtk.export(tmp).map_err(|e| Error::Vtk {
                path: path.clone(),
                message: e.to_string(),
            })
        })?;
        self.written.push((t, name));
        self.write_collection()?;
        if self.written.len() == 1 {
            self.remove_stale()?;
        }
        Ok(())
    }

    /// Removes the files of `dir` named as files of this series ([`series_index`]) that the
    /// collection does not list: an earlier run's samples (directories of such a name are left
    /// alone, and so is every other file).
    fn remove_stale(&self) -> Result<()> {
        let dir = &self.dir;
        for entry in std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))? {
            let entry = entry.map_err(|e| Error::io(dir, e))?;
            let path = entry.path();
            let Some(name) = path.file_name().and_then(|n| n.to_str()) else {
                continue;
            };
            let stale = series_index(&self.stem, name).is_some()
                && !self.written.iter().any(|(_, f)| f == name)
                && !entry.file_type().map_err(|e| Error::io(&path, e))?.is_dir();
            if stale {
                std::fs::remove_file(&path).map_err(|e| Error::io(&path, e))?;
            }
        }
        Ok(())
    }

    /// The `.pvd` collection of the files written so far.
    pub fn collection_path(&self) -> PathBuf {
        self.dir.join(format!("{}.pvd", self.stem))
    }

    fn write_collection(&self) -> Result<()> {
        let mut xml = String::from(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" \
             byte_order=\"LittleEndian\">\n  <Collection>\n",
        );
        for (t, file) in &self.written {
            xml.push_str(&format!(
                "    <DataSet timestep=\"{t:.12e}\" group=\"\" part=\"0\" file=\"{file}\"/>\n"
            ));
        }
        xml.push_str("  </Collection>\n</VTKFile>\n");
        super::atomic::write_bytes(&self.collection_path(), xml)
    }
}

/// A point or cell array of a `.vtu` file written by [`VtuSeries`], as f64 values.
pub fn read_array(path: &Path, name: &str) -> Result<Vec<f64>> {
    let err = |message: String| Error::Vtk {
        path: path.to_path_buf(),
        message,
    };
    let vtk = Vtk::import(path).map_err(|e| err(e.to_string()))?;
    let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
        return Err(err("not an unstructured grid".into()));
    };
    let piece = pieces
        .into_iter()
        .next()
        .ok_or_else(|| err("no piece".into()))?
        .into_loaded_piece_data(None)
        .map_err(|e| err(e.to_string()))?;
    let data = piece.data;
    data.point
        .iter()
        .chain(&data.cell)
        .find_map(|a| match a {
            Attribute::DataArray(arr) if arr.name == name => arr.data.clone().cast_into::<f64>(),
            _ => None,
        })
        .ok_or_else(|| err(format!("no f64 array `{name}`")))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The series' file names are recognised exactly as the writer makes them.
    #[test]
    fn series_files_are_recognised_by_the_writers_exact_pattern() {
        for (name, index) in [
            ("block2d_000000.vtu", Some(0)),
            ("block2d_000012.vtu", Some(12)),
            ("block2d_1234567.vtu", Some(1234567)),
            ("block2d_12.vtu", None),
            ("block2d_0000012.vtu", None),
            ("block2d_+00012.vtu", None),
            ("block2d_000012.vtu.bak", None),
            ("block2d_000012.VTU", None),
            ("block2d.pvd", None),
            ("block2d_x_000012.vtu", None),
            ("block3d_000012.vtu", None),
            ("my_block2d_000012.vtu", None),
        ] {
            assert_eq!(series_index("block2d", name), index, "{name}");
        }
        assert_eq!(series_index("block2d", &series_name("block2d", 7)), Some(7));
    }

    /// Every VTK node maps to a distinct local node, for every element family.
    #[test]
    fn vtk_order_is_a_permutation() {
        for shape in [Shape::Simplex, Shape::Tensor] {
            for dim in [2, 3] {
                for degree in [1, 2] {
                    let el = RefElement { shape, dim, degree };
                    let (_, order) = vtk_order(&el);
                    let mut sorted = order.clone();
                    sorted.sort_unstable();
                    assert_eq!(sorted, (0..el.n_nodes()).collect::<Vec<_>>(), "{el:?}");
                }
            }
        }
    }
}
