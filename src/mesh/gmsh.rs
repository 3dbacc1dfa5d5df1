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
//! - Nodes used by no cell (geometry points) are dropped. Node tags are read as the file lists
//!   them, in any order; a tag listed twice is refused.
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

/// mshio's parse error on one line, without its hex dump of the bytes (up to 700 of them):
/// `in element section, in element entity block (2 of 2): an invalid element definition …`;
/// for its "Unknown error" (a section not closed), the section whose `$End…` line is missing.
fn parse_error(e: &mshio::MshParserError<&[u8]>, bytes: &[u8]) -> String {
    let text = e.to_string();
    let text = text.split("Hex dump").next().unwrap_or_default();
    let mut parts: Vec<&str> = text
        .lines()
        .map(|l| l.trim().trim_end_matches(','))
        .filter(|l| !l.is_empty() && *l != "During parsing...")
        .collect();
    let last = parts.pop().unwrap_or_default();
    let last = last.trim_start_matches("an error occurred: ");
    let text = match parts.is_empty() {
        true => last.to_string(),
        false => format!("{}: {last}", parts.join(", ")),
    };
    if !text.contains("Unknown error") {
        return text;
    }
    let lines: Vec<&[u8]> = bytes
        .split(|&b| b == b'\n')
        .map(|l| l.trim_ascii())
        .collect();
    let unclosed = lines.iter().enumerate().find_map(|(i, l)| {
        let name = l.strip_prefix(b"$").filter(|n| !n.starts_with(b"End"))?;
        let end = [b"$End".as_slice(), name].concat();
        (!lines[i + 1..].contains(&end.as_slice())).then(|| String::from_utf8_lossy(name))
    });
    match unclosed {
        Some(name) => format!("section ${name} has no $End{name} line (a truncated file?)"),
        None => text,
    }
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
        let msh = mshio::parse_msh_bytes(bytes.as_slice()).map_err(|e| {
            err(format!(
                "not a readable MSH 4.1 file: {}",
                parse_error(&e, &bytes)
            ))
        })?;
        let (coords, tag_index, node_tags) = nodes(&msh.data, &bytes).map_err(&err)?;
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
                    node_tags[i],
                    crate::error::short(coords[i][2])
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
        // The node of `tag` in element `element` (its Gmsh tag), which names an unknown one.
        let index = |element: u64, tag: u64| -> std::result::Result<usize, String> {
            (self.tag_index)(tag).ok_or_else(|| {
                format!("element {element} refers to node {tag}, which $Nodes does not list")
            })
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
                    .map(|&t| index(e.element_tag, t))
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
        let (mut faces, mut face_tags) = (Vec::new(), Vec::new());
        for block in elements
            .element_blocks
            .iter()
            .filter(|b| b.entity_dim as usize == dim - 1 && on_contact.contains(&b.entity_tag))
        {
            let t = block.element_type;
            let vertices = match t {
                ElementType::Lin2 | ElementType::Lin3 => 2,
                ElementType::Tri3 | ElementType::Tri6 => 3,
                ElementType::Qua4 | ElementType::Qua8 | ElementType::Qua9 => 4,
                _ => 0,
            };
            if vertices != n_vert {
                let e = &block.elements[0];
                return Err(format!(
                    "element {} (nodes {:?}) of group `{group}` is a {t:?}: no face of the \
                     mesh's {} cells (their faces have {n_vert} vertices)",
                    e.element_tag,
                    e.nodes,
                    element.cells()
                ));
            }
            for e in &block.elements {
                let f: Vec<usize> = e.nodes[..n_vert.min(e.nodes.len())]
                    .iter()
                    .map(|&t| index(e.element_tag, t))
                    .collect::<std::result::Result<_, _>>()?;
                if let Some(&twice) = crate::util::first_repeated(&f) {
                    return Err(format!(
                        "element {} of group `{group}` has node {} twice: a degenerate face",
                        e.element_tag, self.node_tags[twice]
                    ));
                }
                faces.push(f);
                face_tags.push((e.element_tag, e.nodes.clone()));
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
        let mesh = Mesh {
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
                faces: face_tags.iter().map(|f| f.0).collect(),
            }),
        };
        // Every face of Γ_C must be a boundary face of the cells (an interior face, a diagonal,
        // a face of no cell would be dropped from Γ_C without a word).
        let mut boundary: Vec<Vec<usize>> = mesh
            .boundary_faces()
            .into_iter()
            .map(|f| {
                let mut k = f.vertices;
                k.sort_unstable();
                k
            })
            .collect();
        boundary.sort_unstable();
        for (f, (tag, file_nodes)) in mesh.contact_faces.iter().flatten().zip(&face_tags) {
            let mut k = f.clone();
            k.sort_unstable();
            if boundary.binary_search(&k).is_err() {
                return Err(format!(
                    "element {tag} (nodes {file_nodes:?}) of group `{group}` is not a boundary \
                     face of the cells{}: an interior face or no face of a cell",
                    cells_group.map_or(String::new(), |b| format!(" of `{b}`"))
                ));
            }
        }
        Ok(mesh)
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
/// index. The tags are read from the file itself (`mshio` keeps them only when they are
/// sparse, and then in a map that hides a repeated tag): the t-th coordinates are node t only
/// when the file lists the tags in that order.
#[allow(clippy::type_complexity)]
fn nodes(
    data: &mshio::MshData<u64, i32, f64>,
    bytes: &[u8],
) -> std::result::Result<(Vec<[f64; 3]>, Box<dyn Fn(u64) -> Option<usize>>, Vec<u64>), String> {
    let n = data.nodes.as_ref().ok_or("no $Nodes section")?;
    let coords: Vec<[f64; 3]> = n
        .node_blocks
        .iter()
        .flat_map(|b| b.nodes.iter().map(|p| [p.x, p.y, p.z]))
        .collect();
    let tags = node_tags(bytes)?;
    if tags.len() != coords.len() {
        return Err(format!(
            "the $Nodes section lists {} node tags for {} nodes",
            tags.len(),
            coords.len()
        ));
    }
    let mut index: HashMap<u64, usize> = HashMap::with_capacity(tags.len());
    for (i, &t) in tags.iter().enumerate() {
        if index.insert(t, i).is_some() {
            return Err(format!("node tag {t} appears twice in the $Nodes section"));
        }
    }
    let lookup: Box<dyn Fn(u64) -> Option<usize>> = Box::new(move |t| index.get(&t).copied());
    Ok((coords, lookup, tags))
}

/// The node tags of the `$Nodes` section in file order (ASCII or binary MSH 4.1).
fn node_tags(bytes: &[u8]) -> std::result::Result<Vec<u64>, String> {
    let find = |hay: &[u8], needle: &[u8]| hay.windows(needle.len()).position(|w| w == needle);
    let head = find(bytes, b"$MeshFormat").ok_or("no $MeshFormat header")?;
    let format: Vec<String> = String::from_utf8_lossy(&bytes[head..bytes.len().min(head + 100)])
        .split_whitespace()
        .skip(1)
        .take(3)
        .map(str::to_string)
        .collect();
    let binary = format.get(1).map(String::as_str) == Some("1");
    let size: usize = format.get(2).and_then(|s| s.parse().ok()).unwrap_or(8);
    let start = find(bytes, b"$Nodes").ok_or("no $Nodes section")? + b"$Nodes".len();
    let body = &bytes[start..];
    let bad = || "a truncated or malformed $Nodes section".to_string();
    let mut tags = Vec::new();
    if binary {
        // After the line break: size_t numEntityBlocks numNodes min max, then per block int
        // dim, tag, parametric, size_t n, n size_t tags, 3n doubles.
        let mut at = body.iter().position(|&b| b == b'\n').ok_or_else(bad)? + 1;
        let mut read = |width: usize| -> std::result::Result<u64, String> {
            let chunk = body.get(at..at + width).ok_or_else(bad)?;
            at += width;
            let mut v = [0u8; 8];
            v[..width.min(8)].copy_from_slice(&chunk[..width.min(8)]);
            Ok(u64::from_le_bytes(v))
        };
        let blocks = read(size)?;
        for _ in 0..3 {
            read(size)?;
        }
        for _ in 0..blocks {
            for _ in 0..3 {
                read(4)?;
            }
            let n = read(size)?;
            for _ in 0..n {
                tags.push(read(size)?);
            }
            for _ in 0..3 * n {
                read(8)?;
            }
        }
    } else {
        let end = find(body, b"$EndNodes").unwrap_or(body.len());
        let text = String::from_utf8_lossy(&body[..end]);
        let tokens: Vec<&str> = text.split_whitespace().collect();
        let mut at = 0;
        let mut next = |skip: usize| -> std::result::Result<u64, String> {
            at += skip;
            let t = tokens.get(at).ok_or_else(bad)?;
            at += 1;
            t.parse().map_err(|_| bad())
        };
        let blocks = next(0)?;
        let mut skip = 3;
        for _ in 0..blocks {
            let n = next(skip + 3)?;
            for _ in 0..n {
                tags.push(next(0)?);
            }
            skip = 3 * n as usize;
        }
    }
    Ok(tags)
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
    // Each higher-order node with the vertices it lies between (2 on an edge, 4 at a
    // quadrilateral's centre, 8 at a hexahedron's): Gmsh lists the edges' nodes, then the
    // faces', then the volume's, so a node is matched within its own kind only (nearest to its
    // place on the degree-1 cell), and a curved edge's node never takes the centre's place.
    let kinds: Vec<(usize, usize, [f64; 3])> = (0..el.n_nodes())
        .filter(|a| !local_vertices.contains(a))
        .map(|a| {
            let (phi, _) = lin.eval(el.node(a));
            let on = phi.iter().filter(|p| p.abs() > 1e-12).count();
            let target =
                std::array::from_fn(|k| vertices.iter().zip(&phi).map(|(&v, p)| p * x[v][k]).sum());
            (on, a, target)
        })
        .collect();
    let mut taken = vec![false; others.len()];
    for &(on, a, target) in &kinds {
        let first = kinds.iter().filter(|k| k.0 < on).count();
        let len = kinds.iter().filter(|k| k.0 == on).count();
        let dist = |g: usize| (0..3).map(|k| (x[g][k] - target[k]).powi(2)).sum::<f64>();
        let best = (first..(first + len).min(others.len()))
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
        .take_while(|l| !l.trim_start().starts_with("$EndPhysicalNames"))
        .filter_map(|l| {
            // Fields separated by any whitespace (Gmsh reads spaces, tabs, a leading space);
            // the quoted name may itself hold spaces.
            let l = l.trim_start();
            let (d, rest) = l.split_once(char::is_whitespace)?;
            let (t, n) = rest.trim_start().split_once(char::is_whitespace)?;
            let n = n.trim().trim_matches('"').to_string();
            Some((d.parse().ok()?, t.parse().ok()?, n))
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A Q9 cell whose bottom edge bulges 0.6 outward (det J > 0 in Gmsh's order) was refused
    /// as inverted: the nearest node to the bottom edge's place was the centre. Edge nodes are
    /// matched among Gmsh's edge nodes, the centre is its last node.
    #[test]
    fn a_strongly_curved_edge_keeps_its_own_node() {
        let el = RefElement {
            shape: Shape::Tensor,
            dim: 2,
            degree: 2,
        };
        let x = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, -0.6, 0.0],
            [1.0, 0.5, 0.0],
            [0.5, 1.0, 0.0],
            [0.0, 0.5, 0.0],
            [0.5, 0.5, 0.0],
        ];
        let gm: Vec<usize> = (0..9).collect();
        // The reference order: lexicographic on the 3 × 3 grid, x fastest.
        assert_eq!(reorder(&el, &gm, &x).unwrap(), [0, 4, 1, 7, 8, 5, 3, 6, 2]);
    }

    /// A 2D MSH 4.1 file: `nodes` (tag, x, y) in the order given, the cells of `cell_type`
    /// (Gmsh's type number) on surface 1 (group `body`), the edges of `edge_type` on curve 1
    /// (group `contact`), the `$PhysicalNames` lines `names` as written.
    pub(crate) fn msh(
        names: &str,
        nodes: &[(u64, f64, f64)],
        (cell_type, cells): (u32, &[&[u64]]),
        (edge_type, edges): (u32, &[&[u64]]),
    ) -> String {
        let (min, max) = (
            nodes.iter().map(|n| n.0).min().unwrap(),
            nodes.iter().map(|n| n.0).max().unwrap(),
        );
        let mut s = format!(
            "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n{names}\n\
             $EndPhysicalNames\n$Entities\n0 1 1 0\n1 0 0 0 1 0 0 1 1 0\n\
             1 0 0 0 1 1 0 1 2 0\n$EndEntities\n$Nodes\n1 {} {min} {max}\n2 1 0 {}\n",
            nodes.len(),
            nodes.len()
        );
        for n in nodes {
            s += &format!("{}\n", n.0);
        }
        for n in nodes {
            s += &format!("{} {} 0\n", n.1, n.2);
        }
        let total = cells.len() + edges.len();
        s += &format!("$EndNodes\n$Elements\n2 {total} 1 {total}\n");
        s += &format!("1 1 {edge_type} {}\n", edges.len());
        let mut tag = 0;
        for e in edges {
            tag += 1;
            s += &format!(
                "{tag} {}\n",
                e.iter().map(u64::to_string).collect::<Vec<_>>().join(" ")
            );
        }
        s += &format!("2 1 {cell_type} {}\n", cells.len());
        for c in cells {
            tag += 1;
            s += &format!(
                "{tag} {}\n",
                c.iter().map(u64::to_string).collect::<Vec<_>>().join(" ")
            );
        }
        s + "$EndElements\n"
    }

    pub(crate) const NAMES: &str = "1 1 \"contact\"\n2 2 \"body\"";

    /// Reads `text` as a 2D mesh with Γ_C the group `contact`.
    pub(crate) fn read_text(text: &str) -> Result<Mesh> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.msh");
        std::fs::write(&path, text).unwrap();
        read(&path, 2, "contact")
    }

    /// The unit square as one Qua4 (nodes 1–4 counter-clockwise from the origin), its bottom
    /// edge 1–2 in `contact`, the nodes listed in `order`.
    fn square(order: [usize; 4]) -> String {
        let all = [(1, 0.0, 0.0), (2, 1.0, 0.0), (3, 1.0, 1.0), (4, 0.0, 1.0)];
        let nodes: Vec<(u64, f64, f64)> = order.iter().map(|&i| all[i]).collect();
        msh(NAMES, &nodes, (3, &[&[1, 2, 3, 4]]), (1, &[&[1, 2]]))
    }

    #[test]
    fn node_tags_in_any_order_are_mapped_by_tag_and_a_repeated_tag_is_refused() {
        let sorted = read_text(&square([0, 1, 2, 3])).unwrap();
        // Tags 4, 3, 2, 1: a contiguous range written in reverse (it was read as node t = the
        // t-th line, the square turned by 180°).
        for order in [[3, 2, 1, 0], [1, 3, 0, 2]] {
            let m = read_text(&square(order)).unwrap();
            for (c, cell) in m.connectivity.iter().enumerate() {
                let x = |cell: &[usize], m: &Mesh| -> Vec<[f64; 3]> {
                    cell.iter().map(|&i| m.nodes[i]).collect()
                };
                assert_eq!(
                    x(cell, &m),
                    x(&sorted.connectivity[c], &sorted),
                    "{order:?}"
                );
            }
            let face: Vec<[f64; 3]> = m.contact_faces.as_ref().unwrap()[0]
                .iter()
                .map(|&i| m.nodes[i])
                .collect();
            assert_eq!(face, [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]], "{order:?}");
        }
        let twice = square([0, 1, 2, 3]).replace("\n3\n4\n", "\n3\n2\n");
        let e = read_text(&twice).unwrap_err().to_string();
        assert!(
            e.contains("t.msh") && e.contains("node tag 2 appears twice"),
            "{e}"
        );
    }

    #[test]
    fn physical_names_are_split_at_any_whitespace() {
        for names in [
            "1  1 \"contact\"\n2\t2 \"body\"",
            " 1 1 \"contact\"\n2 2 \"body\"",
            "1\t 1\t\"contact\"\n 2 2  \"the body\"",
        ] {
            let m = read_text(&square([0, 1, 2, 3]).replace(NAMES, names));
            assert!(m.is_ok(), "{names:?}: {}", m.unwrap_err());
        }
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.msh");
        let text = square([0, 1, 2, 3]).replace(NAMES, "1 1 \"contact\"\n2 2 \"the body\"");
        std::fs::write(&path, text).unwrap();
        let m = read_bodies(&path, 2, &[("the body", "contact")]).unwrap();
        assert_eq!(m[0].connectivity.len(), 1);
    }

    /// Two unit squares side by side (nodes 1–6, cells 1-2-5-4 and 2-3-6-5), Γ_C `edges`.
    fn two_squares(edges: &[&[u64]]) -> String {
        let nodes = [
            (1, 0.0, 0.0),
            (2, 1.0, 0.0),
            (3, 2.0, 0.0),
            (4, 0.0, 1.0),
            (5, 1.0, 1.0),
            (6, 2.0, 1.0),
        ];
        msh(
            NAMES,
            &nodes,
            (3, &[&[1, 2, 5, 4], &[2, 3, 6, 5]]),
            (1, edges),
        )
    }

    #[test]
    fn contact_faces_that_are_no_boundary_face_of_the_cells_are_refused() {
        assert!(read_text(&two_squares(&[&[1, 2], &[3, 2]])).is_ok());
        // The interior edge 2–5 (it was dropped from Γ_C), a diagonal 1–5 of no cell.
        for (edge, name) in [
            ([5, 2], "element 2 (nodes [5, 2])"),
            ([1, 5], "element 2 (nodes [1, 5])"),
        ] {
            let e = read_text(&two_squares(&[&[1, 2], &edge]))
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("t.msh") && e.contains(name) && e.contains("not a boundary face"),
                "{e}"
            );
        }
        // A Qua4 face on a tet: it was cut to its first three nodes.
        let tet = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n2 1 \"contact\"\n\
                   3 2 \"body\"\n$EndPhysicalNames\n$Entities\n0 0 1 1\n\
                   1 0 0 0 1 1 0 1 1 0\n1 0 0 0 1 1 1 1 2 0\n$EndEntities\n\
                   $Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n\
                   $Elements\n2 2 1 2\n2 1 2 1\n1 1 2 3\n3 1 4 1\n2 1 2 3 4\n$EndElements\n";
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("tet.msh");
        std::fs::write(&path, tet).unwrap();
        assert!(read(&path, 3, "contact").is_ok());
        let quad = tet.replace("2 1 2 1\n1 1 2 3\n", "2 1 3 1\n1 1 2 3 4\n");
        std::fs::write(&path, quad).unwrap();
        let e = read(&path, 3, "contact").unwrap_err().to_string();
        assert!(
            e.contains("tet.msh")
                && e.contains("element 1 (nodes [1, 2, 3, 4])")
                && e.contains("Qua4"),
            "{e}"
        );
    }
}
