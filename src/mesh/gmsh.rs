//! Gmsh meshes (MSH 4.1, ASCII or binary, read with `mshio`) as a [`Mesh`].
//!
//! - Cells: the elements of dimension d (one family): 3-/6-node triangles, 4-/9-node
//!   quadrilaterals (2D), 4-/10-node tetrahedra, 8-/27-node hexahedra (3D). Gmsh's vertex order is
//!   mapped to the reference element's (quadrilateral and hexahedron vertices counter-clockwise →
//!   lexicographic); second-order nodes are matched to the reference nodes geometrically (the
//!   node of the cell nearest the image of the reference node under the cell's degree-1 map),
//!   which holds for any reasonably shaped cell and does not depend on Gmsh's edge numbering.
//! - Γ_C: the elements of dimension d − 1 on the entities of the physical group named `group`
//!   (the `$PhysicalNames` section, which `mshio` does not read, is parsed here).
//! - Several bodies in one file ([`read_bodies`], the two-body cases): each body is the cells
//!   of the entities of its physical group of dimension d (`body1`, `body2`) with its own Γ_C
//!   group (`contact1`, `contact2`), and its own nodes (the meshes need not match across the
//!   interface).
//! - Nodes used by no cell (geometry points) are dropped. Node tags are taken in file order from
//!   the smallest tag when they are dense (Gmsh's numbering), else from the tags themselves.
//!
//! Every failure names the file and the entity at fault.

use super::Mesh;
use crate::element::reference::{RefElement, Shape};
use crate::error::{Error, Result};
use mshio::ElementType;
use std::collections::HashMap;
use std::path::Path;

/// Reads the Gmsh file at `path` as a mesh of dimension `dim` (every cell of dimension `dim`)
/// whose Γ_C is the physical group `group`.
pub fn read(path: &Path, dim: usize, group: &str) -> Result<Mesh> {
    File::open(path, dim)?.mesh(None, group)
}

/// Reads the Gmsh file at `path` holding several bodies: for each `(cells, contact)` pair of
/// physical group names, the body made of the cells of dimension `dim` of the group `cells`
/// (its own nodes, numbered from 0) whose Γ_C is the group `contact` (faces on that body's
/// cells). Bodies may touch or overlap in the file: each keeps its own copy of shared nodes.
pub fn read_bodies(path: &Path, dim: usize, groups: &[(&str, &str)]) -> Result<Vec<Mesh>> {
    let file = File::open(path, dim)?;
    groups
        .iter()
        .map(|&(cells, contact)| file.mesh(Some(cells), contact))
        .collect()
}

/// A parsed Gmsh file: its text, its mesh data, its node coordinates and physical names.
struct File {
    origin: String,
    dim: usize,
    msh: mshio::MshFile<u64, i32, f64>,
    coords: Vec<[f64; 3]>,
    tag_index: Box<dyn Fn(u64) -> Option<usize>>,
    /// The tag of each node of `coords`.
    node_tags: Vec<u64>,
    names: Vec<(usize, i32, String)>,
}

impl File {
    /// Reads and checks the file (version, sections, dimension of the cells).
    fn open(path: &Path, dim: usize) -> Result<Self> {
        let origin = path.display().to_string();
        let err = |m: String| Error::Mesh {
            origin: origin.clone(),
            message: m,
        };
        let bytes = crate::input::MESH_FILE.read(path)?;
        check_version(&bytes).map_err(&err)?;
        let msh = mshio::parse_msh_bytes(bytes.as_slice())
            .map_err(|e| err(format!("not a readable MSH 4.1 file: {e}")))?;
        let (coords, tag_index, node_tags) = nodes(&msh.data).map_err(&err)?;
        let elements = msh
            .data
            .elements
            .as_ref()
            .ok_or_else(|| err("no $Elements section".into()))?;
        if let Some(top) = elements
            .element_blocks
            .iter()
            .map(|b| b.entity_dim as usize)
            .max()
        {
            if top != dim {
                return Err(err(format!(
                    "the mesh's cells are {top}-dimensional: a {top}D mesh given to a {dim}D case"
                )));
            }
        }
        if dim == 2 {
            if let Some(i) = coords.iter().position(|x| x[2] != 0.0) {
                return Err(err(format!(
                    "node {} of a 2D mesh has z = {} ≠ 0",
                    node_tags[i], coords[i][2]
                )));
            }
        }
        let names = physical_names(&bytes);
        Ok(Self {
            origin,
            dim,
            msh,
            coords,
            tag_index,
            node_tags,
            names,
        })
    }

    /// The tag of the physical group `name` of dimension `dim`, or an error listing the groups.
    fn group(&self, name: &str, dim: usize) -> std::result::Result<i32, String> {
        self.names
            .iter()
            .find(|(d, _, n)| *d == dim && n == name)
            .map(|(_, t, _)| *t)
            .ok_or_else(|| {
                let known: Vec<String> = self
                    .names
                    .iter()
                    .map(|(d, _, n)| format!("`{n}` (dim {d})"))
                    .collect();
                format!(
                    "no physical group `{name}` of dimension {dim} (groups: {})",
                    if known.is_empty() {
                        "none".into()
                    } else {
                        known.join(", ")
                    }
                )
            })
    }

    /// The mesh of the cells of the physical group `cells` (every cell when None) with Γ_C the
    /// physical group `group`.
    fn mesh(&self, cells_group: Option<&str>, group: &str) -> Result<Mesh> {
        self.build(cells_group, group)
            .map_err(|message| Error::Mesh {
                origin: self.origin.clone(),
                message,
            })
    }

    fn build(&self, cells_group: Option<&str>, group: &str) -> std::result::Result<Mesh, String> {
        let (dim, coords, data) = (self.dim, &self.coords, &self.msh.data);
        let elements = data.elements.as_ref().ok_or("no $Elements section")?;
        let index = |tag: u64| -> std::result::Result<usize, String> {
            (self.tag_index)(tag).ok_or_else(|| format!("element refers to unknown node {tag}"))
        };
        let body = match cells_group {
            Some(name) => Some(entities(data, dim, self.group(name, dim)?)),
            None => None,
        };
        let of_body = |tag: i32| body.as_ref().is_none_or(|e| e.contains(&tag));
        // Cells: the blocks of dimension `dim` (of the body's entities), one family.
        let mut element: Option<(RefElement, ElementType)> = None;
        let (mut cells, mut cell_tags): (Vec<Vec<usize>>, Vec<u64>) = (Vec::new(), Vec::new());
        for block in elements
            .element_blocks
            .iter()
            .filter(|b| b.entity_dim as usize == dim && of_body(b.entity_tag))
        {
            let el = family(block.element_type, dim).ok_or_else(|| {
                format!(
                    "unsupported element type {:?} in the cells of entity {} (supported: \
                     Tri3/Tri6/Qua4/Qua9 in 2D, Tet4/Tet10/Hex8/Hex27 in 3D)",
                    block.element_type, block.entity_tag
                )
            })?;
            match element {
                Some((e, t)) if e != el => {
                    return Err(format!(
                        "mixed cell types {t:?} and {:?}: one element family per mesh",
                        block.element_type
                    ))
                }
                _ => element = Some((el, block.element_type)),
            }
            for e in &block.elements {
                let gm: Vec<usize> = e
                    .nodes
                    .iter()
                    .map(|&t| index(t))
                    .collect::<std::result::Result<_, _>>()?;
                cells.push(
                    reorder(&el, &gm, coords)
                        .map_err(|m| format!("element {}: {m}", e.element_tag))?,
                );
                cell_tags.push(e.element_tag);
            }
        }
        let Some((element, _)) = element else {
            if let Some(name) = cells_group {
                return Err(format!(
                    "physical group `{name}` has no element of dimension {dim}"
                ));
            }
            let dims: Vec<i32> = elements
                .element_blocks
                .iter()
                .map(|b| b.entity_dim)
                .collect();
            return Err(format!(
                "no {dim}-dimensional cell (element blocks of dimensions {dims:?}: a {}D mesh \
                 given to a {dim}D case?)",
                dims.iter().max().copied().unwrap_or(0)
            ));
        };
        // Γ_C: faces on the entities of the physical group.
        let on_contact = entities(data, dim - 1, self.group(group, dim - 1)?);
        let n_vert = if dim == 2 {
            2
        } else if element.shape == Shape::Simplex {
            3
        } else {
            4
        };
        let mut faces = Vec::new();
        for block in elements
            .element_blocks
            .iter()
            .filter(|b| b.entity_dim as usize == dim - 1 && on_contact.contains(&b.entity_tag))
        {
            for e in &block.elements {
                let f: Vec<usize> = e.nodes[..n_vert.min(e.nodes.len())]
                    .iter()
                    .map(|&t| index(t))
                    .collect::<std::result::Result<_, _>>()?;
                if let Some(&twice) = crate::util::first_repeated(&f) {
                    return Err(format!(
                        "element {} of group `{group}` has node {} twice: a degenerate face",
                        e.element_tag, self.node_tags[twice]
                    ));
                }
                faces.push(f);
            }
        }
        if faces.is_empty() {
            return Err(format!(
                "physical group `{group}` has no element of dimension {}",
                dim - 1
            ));
        }
        // Keep the nodes of the cells only, in file order.
        let mut used = vec![usize::MAX; coords.len()];
        let (mut nodes, mut node_tags) = (Vec::new(), Vec::new());
        for c in &mut cells {
            for i in c.iter_mut() {
                if used[*i] == usize::MAX {
                    used[*i] = nodes.len();
                    nodes.push(coords[*i]);
                    node_tags.push(self.node_tags[*i]);
                }
                *i = used[*i];
            }
        }
        for f in &mut faces {
            for i in f.iter_mut() {
                if used[*i] == usize::MAX {
                    return Err(format!(
                        "a face of group `{group}` has node {} on no cell{}",
                        self.node_tags[*i],
                        cells_group.map_or(String::new(), |b| format!(" of `{b}`"))
                    ));
                }
                *i = used[*i];
            }
        }
        let h = faces
            .iter()
            .map(|f| {
                let (a, b) = (nodes[f[0]], nodes[f[1]]);
                (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt()
            })
            .sum::<f64>()
            / faces.len() as f64;
        Ok(Mesh {
            origin: match cells_group {
                Some(name) => format!("{} (`{name}`)", self.origin),
                None => self.origin.clone(),
            },
            element,
            nodes,
            connectivity: cells,
            h,
            contact_faces: Some(faces),
            tags: Some(super::Tags {
                nodes: node_tags,
                cells: cell_tags,
            }),
        })
    }
}

/// Refuses files that are not MSH 4.x with a message naming the version found.
fn check_version(bytes: &[u8]) -> std::result::Result<(), String> {
    let text = String::from_utf8_lossy(&bytes[..bytes.len().min(200)]);
    let version = text
        .lines()
        .skip_while(|l| l.trim() != "$MeshFormat")
        .nth(1)
        .and_then(|l| l.split_whitespace().next().map(str::to_string));
    match version.as_deref() {
        Some(v) if v.starts_with("4.1") => Ok(()),
        Some(v) => Err(format!(
            "MSH version {v} is not supported (only 4.1: `gmsh -format msh41`)"
        )),
        None => Err("no $MeshFormat header: not a Gmsh MSH file".into()),
    }
}

/// Node coordinates in file order, the map from a node tag to its index, and the tag of each
/// index.
#[allow(clippy::type_complexity)]
fn nodes(
    data: &mshio::MshData<u64, i32, f64>,
) -> std::result::Result<(Vec<[f64; 3]>, Box<dyn Fn(u64) -> Option<usize>>, Vec<u64>), String> {
    let n = data.nodes.as_ref().ok_or("no $Nodes section")?;
    let mut coords = Vec::new();
    let mut sparse: HashMap<u64, usize> = HashMap::new();
    let dense = n.node_blocks.iter().all(|b| b.node_tags.is_none());
    for b in &n.node_blocks {
        if let Some(tags) = &b.node_tags {
            for (&t, &i) in tags {
                sparse.insert(t, coords.len() + i);
            }
        }
        coords.extend(b.nodes.iter().map(|p| [p.x, p.y, p.z]));
    }
    let (min, len) = (n.min_node_tag, coords.len());
    let tags: Vec<u64> = if dense {
        (0..len as u64).map(|i| min + i).collect()
    } else {
        let mut tags = vec![0; len];
        for (&t, &i) in &sparse {
            tags[i] = t;
        }
        tags
    };
    let lookup: Box<dyn Fn(u64) -> Option<usize>> = if dense {
        Box::new(move |t| t.checked_sub(min).map(|i| i as usize).filter(|&i| i < len))
    } else {
        Box::new(move |t| sparse.get(&t).copied())
    };
    Ok((coords, lookup, tags))
}

/// The reference element of a Gmsh cell type in dimension `dim`.
fn family(t: ElementType, dim: usize) -> Option<RefElement> {
    let (shape, d, degree) = match t {
        ElementType::Tri3 => (Shape::Simplex, 2, 1),
        ElementType::Tri6 => (Shape::Simplex, 2, 2),
        ElementType::Qua4 => (Shape::Tensor, 2, 1),
        ElementType::Qua9 => (Shape::Tensor, 2, 2),
        ElementType::Tet4 => (Shape::Simplex, 3, 1),
        ElementType::Tet10 => (Shape::Simplex, 3, 2),
        ElementType::Hex8 => (Shape::Tensor, 3, 1),
        ElementType::Hex27 => (Shape::Tensor, 3, 2),
        _ => return None,
    };
    (d == dim).then_some(RefElement { shape, dim, degree })
}

/// Gmsh's node list of one cell in the reference element's order.
fn reorder(
    el: &RefElement,
    gm: &[usize],
    x: &[[f64; 3]],
) -> std::result::Result<Vec<usize>, String> {
    if gm.len() != el.n_nodes() {
        return Err(format!("{} nodes, expected {}", gm.len(), el.n_nodes()));
    }
    // Gmsh lists the vertices in the conventional order (tensor: counter-clockwise).
    let mut out = vec![usize::MAX; el.n_nodes()];
    for (a, &v) in el.cyclic_vertices().into_iter().zip(gm) {
        out[a] = v;
    }
    if el.degree == 1 {
        return Ok(out);
    }
    // The vertices in the reference (degree-1 basis) order, for the degree-1 map.
    let local_vertices = el.vertices();
    let vertices: Vec<usize> = local_vertices.iter().map(|&a| out[a]).collect();
    let lin = RefElement { degree: 1, ..*el };
    let others: Vec<usize> = gm
        .iter()
        .copied()
        .filter(|g| !vertices.contains(g))
        .collect();
    let mut taken = vec![false; others.len()];
    for a in (0..el.n_nodes()).filter(|a| !local_vertices.contains(a)) {
        let (phi, _) = lin.eval(el.node(a));
        let target: [f64; 3] =
            std::array::from_fn(|k| vertices.iter().zip(&phi).map(|(&v, p)| p * x[v][k]).sum());
        let dist = |g: usize| (0..3).map(|k| (x[g][k] - target[k]).powi(2)).sum::<f64>();
        let best = (0..others.len())
            .filter(|&j| !taken[j])
            .min_by(|&i, &j| dist(others[i]).total_cmp(&dist(others[j])))
            .ok_or("too few second-order nodes")?;
        taken[best] = true;
        out[a] = others[best];
    }
    Ok(out)
}

/// `(dimension, tag, name)` of every physical group (the `$PhysicalNames` section).
fn physical_names(bytes: &[u8]) -> Vec<(usize, i32, String)> {
    let text = String::from_utf8_lossy(bytes);
    let Some(start) = text.find("$PhysicalNames") else {
        return Vec::new();
    };
    text[start..]
        .lines()
        .skip(2)
        .take_while(|l| !l.starts_with("$EndPhysicalNames"))
        .filter_map(|l| {
            let mut it = l.splitn(3, ' ');
            let d = it.next()?.trim().parse().ok()?;
            let t = it.next()?.trim().parse().ok()?;
            let n = it.next()?.trim().trim_matches('"').to_string();
            Some((d, t, n))
        })
        .collect()
}

/// Tags of the entities of dimension `dim` carrying the physical tag `ptag`.
fn entities(data: &mshio::MshData<u64, i32, f64>, dim: usize, ptag: i32) -> Vec<i32> {
    let Some(e) = &data.entities else {
        return Vec::new();
    };
    let pick = |tag: i32, phys: &[i32]| phys.contains(&ptag).then_some(tag);
    match dim {
        0 => e
            .points
            .iter()
            .filter_map(|p| pick(p.tag, &p.physical_tags))
            .collect(),
        1 => e
            .curves
            .iter()
            .filter_map(|c| pick(c.tag, &c.physical_tags))
            .collect(),
        2 => e
            .surfaces
            .iter()
            .filter_map(|s| pick(s.tag, &s.physical_tags))
            .collect(),
        _ => e
            .volumes
            .iter()
            .filter_map(|v| pick(v.tag, &v.physical_tags))
            .collect(),
    }
}
