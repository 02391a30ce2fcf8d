//! Images laid on faces: what a tag's material shows instead of a flat
//! colour, and how large one copy of the image is in the world.

/// Index into [`Scene::textures`](super::Scene::textures).
pub type TextureId = u32;

/// A PNG image and its size in the world.
///
/// Exporters project it onto every face of a textured tag in world units
/// (one copy per `size` metres, repeating), so pieces of a split face
/// continue one another's pattern.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// Short name, unique within a scene (the file stem, numbered when two
    /// files share one): exporters name the image and the file beside an
    /// OBJ after it.
    pub name: String,
    /// The PNG file, as read.
    pub png: Vec<u8>,
    /// Width and height of the image in pixels (from the PNG header).
    pub pixels: [u32; 2],
    /// Width and height of one copy of the image in world units (metres).
    pub size: [f32; 2],
}

impl Texture {
    /// A texture from the bytes of a PNG file, one copy covering
    /// `size` (width, height) world units.
    ///
    /// # Errors
    ///
    /// When `png` is not a PNG file (its signature and header), when its
    /// width or height is 0, or when a size is not a positive finite
    /// number; the message says which.
    pub fn from_png(name: &str, png: Vec<u8>, size: [f32; 2]) -> Result<Texture, String> {
        const SIGNATURE: &[u8; 8] = b"\x89PNG\r\n\x1a\n";
        if png.len() < 24 || &png[..8] != SIGNATURE || &png[12..16] != b"IHDR" {
            return Err("not a PNG image (textures are PNG files)".into());
        }
        let be = |o: usize| u32::from_be_bytes([png[o], png[o + 1], png[o + 2], png[o + 3]]);
        let pixels = [be(16), be(20)];
        if pixels.contains(&0) {
            return Err(format!("the PNG image is {}×{} pixels", pixels[0], pixels[1]));
        }
        if !size.iter().all(|s| s.is_finite() && *s > 0.0) {
            return Err(format!("a texture's size must be positive, found {} × {}", size[0], size[1]));
        }
        Ok(Texture { name: name.to_string(), png, pixels, size })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_texture_reads_its_size_from_the_png_header_and_refuses_anything_else() {
        let mut png = b"\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR".to_vec();
        png.extend_from_slice(&[0, 0, 1, 0, 0, 0, 0, 64, 8, 2, 0, 0, 0]);
        let t = Texture::from_png("brick", png.clone(), [2.0, 1.0]).unwrap();
        assert_eq!((t.pixels, t.size, t.png.len()), ([256, 64], [2.0, 1.0], png.len()));
        assert!(Texture::from_png("x", b"GIF89a".to_vec(), [1.0, 1.0]).unwrap_err().contains("not a PNG"));
        assert!(Texture::from_png("x", png.clone(), [0.0, 1.0]).unwrap_err().contains("positive"));
        assert!(Texture::from_png("x", png.clone(), [f32::NAN, 1.0]).unwrap_err().contains("positive"));
        let mut empty = png;
        empty[16..20].copy_from_slice(&[0; 4]);
        assert!(Texture::from_png("x", empty, [1.0, 1.0]).unwrap_err().contains("0×64"));
    }
}
