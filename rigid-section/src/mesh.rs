//! Closed triangle meshes read from Wavefront OBJ files, for rigid bodies of
//! any shape (a parachutist or cargo, dissertation §2.4). Written by hand rather
//! than with an OBJ crate so that every problem names the line it is on.
//!
//! Read: `v x y z` vertices and `f i j k …` faces (1-based or negative
//! indices, `i/t/n` forms allowed, polygons split into a fan). Other lines
//! (normals, texture coordinates, groups, materials, comments) are skipped.
//! The mesh must be closed and consistently oriented — every edge shared by
//! exactly two faces, once in each direction — with its faces pointing out,
//! because its volume, mass and inertia come from the divergence theorem
//! (dissertation eq. 2.6 over the enclosed solid).

use std::collections::HashMap;
use std::fmt;
use std::path::{Path, PathBuf};

/// A closed, outward-oriented triangle mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct TriangleMesh {
    pub vertices: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
}

/// What is wrong with a mesh file, and where.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshError {
    pub file: PathBuf,
    /// 1-based line, when the problem has one.
    pub line: Option<usize>,
    pub message: String,
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(l) = self.line {
            write!(f, ":{l}")?;
        }
        write!(f, ": {}", self.message)
    }
}

impl std::error::Error for MeshError {}

impl TriangleMesh {
    /// Read and check an OBJ file.
    pub fn read_obj(path: &Path) -> Result<TriangleMesh, MeshError> {
        let fail = |line: Option<usize>, message: String| MeshError {
            file: path.to_path_buf(),
            line,
            message,
        };
        let meta = std::fs::metadata(path)
            .map_err(|e| fail(None, format!("cannot read the mesh: {e}")))?;
        if !meta.is_file() {
            return Err(fail(
                None,
                "cannot read the mesh: it is not a regular file".into(),
            ));
        }
        let text = std::fs::read_to_string(path)
            .map_err(|e| fail(None, format!("cannot read the mesh: {e}")))?;
        let mesh = TriangleMesh::parse_obj(&text).map_err(|(l, m)| fail(l, m))?;
        mesh.check_closed().map_err(|(l, m)| fail(l, m))?;
        Ok(mesh)
    }

    /// Parse OBJ text; an error carries its 1-based line.
    fn parse_obj(text: &str) -> Result<TriangleMesh, (Option<usize>, String)> {
        let mut mesh = TriangleMesh {
            vertices: Vec::new(),
            triangles: Vec::new(),
        };
        for (n, raw) in text.lines().enumerate() {
            let line = n + 1;
            let mut words = raw.split('#').next().unwrap_or("").split_whitespace();
            match words.next() {
                Some("v") => {
                    let xyz: Vec<&str> = words.collect();
                    // A fourth value (w or a colour) may follow x y z.
                    if xyz.len() < 3 {
                        return Err((Some(line), "a vertex needs x y z".into()));
                    }
                    let mut v = [0.0; 3];
                    for (c, w) in v.iter_mut().zip(&xyz) {
                        *c = w.parse().ok().filter(|x: &f64| x.is_finite()).ok_or((
                            Some(line),
                            format!("vertex coordinate `{w}` is not a finite number"),
                        ))?;
                    }
                    mesh.vertices.push(v);
                }
                Some("f") => {
                    let count = mesh.vertices.len();
                    let face = words
                        .map(|w| vertex_index(w, count))
                        .collect::<Result<Vec<u32>, String>>()
                        .map_err(|m| (Some(line), m))?;
                    if face.len() < 3 {
                        return Err((Some(line), "a face needs at least 3 vertices".into()));
                    }
                    for k in 1..face.len() - 1 {
                        mesh.triangles.push([face[0], face[k], face[k + 1]]);
                    }
                }
                _ => {}
            }
        }
        if mesh.triangles.len() < 4 {
            return Err((
                None,
                format!(
                    "has {} triangles: a closed surface needs at least 4",
                    mesh.triangles.len()
                ),
            ));
        }
        Ok(mesh)
    }

    /// Every directed edge exactly once and its reverse exactly once; the
    /// enclosed volume positive.
    fn check_closed(&self) -> Result<(), (Option<usize>, String)> {
        let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
        for (t, tri) in self.triangles.iter().enumerate() {
            if tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] {
                return Err((None, format!("triangle {t} repeats a vertex")));
            }
            for k in 0..3 {
                let e = (tri[k], tri[(k + 1) % 3]);
                if directed.insert(e, t).is_some() {
                    return Err((None, format!(
                        "the edge from vertex {} to vertex {} (1-based) runs the same way in two faces: the faces are not consistently oriented, or more than two faces share it",
                        e.0 + 1, e.1 + 1
                    )));
                }
            }
        }
        for &(a, b) in directed.keys() {
            if !directed.contains_key(&(b, a)) {
                return Err((None, format!(
                    "the edge between vertices {} and {} (1-based) belongs to one face only: the mesh is not closed",
                    a + 1, b + 1
                )));
            }
        }
        if self.volume() <= 0.0 {
            return Err((
                None,
                "encloses a negative volume: its faces point inward (reverse their vertex order)"
                    .into(),
            ));
        }
        Ok(())
    }

    /// Enclosed volume [m³]: the divergence theorem over the faces.
    pub fn volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.vertices[i as usize]);
                let cross = [
                    b[1] * c[2] - b[2] * c[1],
                    b[2] * c[0] - b[0] * c[2],
                    b[0] * c[1] - b[1] * c[0],
                ];
                (a[0] * cross[0] + a[1] * cross[1] + a[2] * cross[2]) / 6.0
            })
            .sum()
    }
}

/// A face entry `i`, `i/t`, `i//n` or `i/t/n`, 1-based or negative (relative).
fn vertex_index(word: &str, count: usize) -> Result<u32, String> {
    let first = word.split('/').next().unwrap_or("");
    let i: i64 = first
        .parse()
        .map_err(|_| format!("face vertex `{word}` is not an index"))?;
    let index = if i > 0 { i - 1 } else { count as i64 + i };
    if i == 0 || index < 0 || index >= count as i64 {
        return Err(format!(
            "face vertex {i} does not exist: {count} vertices are defined above this line"
        ));
    }
    Ok(index as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    const CUBE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
        f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

    #[test]
    fn unit_cube_encloses_unit_volume() {
        let m = TriangleMesh::parse_obj(CUBE).unwrap();
        m.check_closed().unwrap();
        assert_eq!(m.triangles.len(), 12);
        assert!((m.volume() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn open_inverted_and_bad_faces_are_refused_with_their_line() {
        let open = CUBE.replace("f 4 1 5 8\n", "");
        let e = TriangleMesh::parse_obj(&open)
            .unwrap()
            .check_closed()
            .unwrap_err();
        assert!(e.1.contains("not closed"), "{}", e.1);
        let inverted = CUBE
            .lines()
            .map(|l| match l.strip_prefix("f ") {
                Some(f) => format!("f {}", f.split(' ').rev().collect::<Vec<_>>().join(" ")),
                None => l.to_string(),
            })
            .collect::<Vec<_>>()
            .join("\n");
        let e = TriangleMesh::parse_obj(&inverted)
            .unwrap()
            .check_closed()
            .unwrap_err();
        assert!(e.1.contains("point inward"), "{}", e.1);
        let e = TriangleMesh::parse_obj(&format!("{CUBE}f 1 2 99\n")).unwrap_err();
        assert_eq!(e.0, Some(15));
        assert!(e.1.contains("99"), "{}", e.1);
        let e = TriangleMesh::parse_obj("v 0 0 x\n").unwrap_err();
        assert_eq!(e.0, Some(1));
    }
}
