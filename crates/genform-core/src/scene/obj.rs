//! Reading the geometry of a Wavefront OBJ text into a [`Mesh`].

use super::Mesh;
use glam::Vec3;

impl Mesh {
    /// Reads the geometry of a Wavefront OBJ text: `v` positions and `f`
    /// faces (`i`, `i/t`, `i//n`, `i/t/n`; negative indices count back;
    /// polygons are fan-triangulated). Other statements are ignored. Errors
    /// name the line.
    pub fn from_obj(name: &str, text: &str) -> Result<Mesh, String> {
        let mut positions = Vec::new();
        let mut triangles = Vec::new();
        let mut face = Vec::new();
        for (ln, line) in text.lines().enumerate() {
            let mut it = line.split_whitespace();
            match it.next() {
                Some("v") => {
                    let mut c = [0f32; 3];
                    for v in &mut c {
                        *v = it
                            .next()
                            .and_then(|t| t.parse::<f32>().ok())
                            .filter(|v| v.is_finite())
                            .ok_or_else(|| format!("line {}: a vertex needs three finite numbers", ln + 1))?;
                    }
                    positions.push(Vec3::from_array(c));
                }
                Some("f") => {
                    face.clear();
                    for t in it {
                        let idx = t.split('/').next().unwrap_or("");
                        let i: i64 = idx.parse().map_err(|_| format!("line {}: bad face index `{t}`", ln + 1))?;
                        let n = positions.len() as i64;
                        let abs = if i < 0 { n + i } else { i - 1 };
                        if abs < 0 || abs >= n {
                            return Err(format!("line {}: face index {i} refers to a missing vertex", ln + 1));
                        }
                        face.push(abs as u32);
                    }
                    if face.len() < 3 {
                        return Err(format!("line {}: a face needs at least 3 vertices", ln + 1));
                    }
                    for i in 1..face.len() - 1 {
                        triangles.push([face[0], face[i], face[i + 1]]);
                    }
                }
                _ => {}
            }
        }
        if triangles.is_empty() {
            return Err("the OBJ file has no faces".into());
        }
        Ok(Mesh { name: name.to_string(), positions, triangles })
    }
}
