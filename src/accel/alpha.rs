//! Cut-outs (glTF `alphaMode` MASK): hits on the parts of a triangle whose alpha is below its
//! material's cutoff do not count, for camera and shadow rays alike, so leaves, fences and decals
//! show what is behind them and cast shadows of their shape.
//!
//! The test runs inside traversal, lane by lane in the leaf tests ([`super::wide::TriangleQuad`]):
//! a cut-out hit must not end a ray's search for its closest hit nor answer a shadow ray. The
//! traversal is generic over a [`HitFilter`]; scenes without cut-outs use [`Opaque`], whose
//! filter is never asked and compiles away, so they pay one branch per query on whether the
//! BVH has a mask (its instruction counts: docs/performance-log.md).

use glam::Vec2;

use crate::material::Material;
use crate::scene::mesh::TriangleMesh;
use crate::texture::{ColorSpace, TextureImage, TextureRef};

/// Decides, hit by hit, whether the triangle is there where a ray crosses it.
pub trait HitFilter {
    /// False when every hit counts: [`Self::keeps`] is then never called.
    const FILTERS: bool;

    /// [`Self::FILTERS`], asked of a value (the traversal holds `&impl HitFilter`).
    #[inline(always)]
    fn filters(&self) -> bool {
        Self::FILTERS
    }

    /// Whether the hit on scene triangle `triangle` at barycentric weights `b1`, `b2` (of its
    /// vertices 1 and 2) counts.
    fn keeps(&self, triangle: u32, b1: f32, b2: f32) -> bool;
}

/// Every hit counts.
pub struct Opaque;

impl HitFilter for Opaque {
    const FILTERS: bool = false;

    #[inline(always)]
    fn keeps(&self, _triangle: u32, _b1: f32, _b2: f32) -> bool {
        true
    }
}

/// The cut-out of one material: its cutoff and alpha factor, and where its alpha texture is
/// (the base colour texture, renumbered into [`AlphaMask::images`]).
#[derive(Clone, Copy, Debug, PartialEq)]
struct MaterialCutout {
    cutoff: f32,
    alpha: f32,
    texture: Option<TextureRef>,
}

/// A scene's cut-outs: what the alpha of any hit is computed from. It owns copies of the few
/// arrays it reads (triangles, texture coordinates, the alpha textures), so that the BVH that
/// holds it needs nothing else; it exists only for scenes with a MASK material.
#[derive(Clone, Debug, PartialEq)]
pub struct AlphaMask {
    /// Per material: its cut-out, if it has one.
    cutouts: Vec<Option<MaterialCutout>>,
    material_of_triangle: Vec<u32>,
    triangles: Vec<[u32; 3]>,
    /// Texture-coordinate sets 0 and 1 per vertex (zeros where the mesh has none).
    uvs: [Vec<Vec2>; 2],
    /// The images the cut-outs read.
    images: Vec<TextureImage>,
}

impl AlphaMask {
    /// The cut-outs of `mesh` with `materials` (whose textures index `images`), or `None` when no
    /// material that a triangle uses has one.
    pub fn new(mesh: &TriangleMesh, materials: &[Material], images: &[TextureImage]) -> Option<Self> {
        let used = mesh.materials_used(materials.len());
        let mut kept_images: Vec<TextureImage> = Vec::new();
        let cutouts: Vec<Option<MaterialCutout>> = materials
            .iter()
            .zip(used)
            .map(|(material, used)| {
                let (cutout, texture) = material.cutout().filter(|_| used)?;
                Some(MaterialCutout {
                    cutoff: cutout.cutoff,
                    alpha: cutout.alpha,
                    texture: texture.map(|mut t| {
                        kept_images.push(images[t.image as usize].clone());
                        t.image = kept_images.len() as u32 - 1;
                        t
                    }),
                })
            })
            .collect();
        if cutouts.iter().all(Option::is_none) {
            return None;
        }
        let zeros = || vec![Vec2::ZERO; mesh.positions.len()];
        Some(Self {
            cutouts,
            material_of_triangle: mesh.material_of_triangle.clone(),
            triangles: mesh.triangles.clone(),
            uvs: [
                mesh.uvs.clone().unwrap_or_else(zeros),
                mesh.uvs1.clone().unwrap_or_else(zeros),
            ],
            images: kept_images,
        })
    }

    /// The alpha of a cut-out material's surface at barycentrics (b1, b2) of `triangle`: the
    /// factor times the texture's alpha at the interpolated texture coordinates.
    fn alpha(&self, cutout: &MaterialCutout, triangle: u32, b1: f32, b2: f32) -> f32 {
        let Some(texture) = &cutout.texture else {
            return cutout.alpha;
        };
        let [i0, i1, i2] = self.triangles[triangle as usize].map(|i| i as usize);
        let uvs = &self.uvs[usize::from(texture.tex_coord.min(1))];
        let uv = (1.0 - b1 - b2) * uvs[i0] + b1 * uvs[i1] + b2 * uvs[i2];
        cutout.alpha * texture.sample(&self.images, uv, ColorSpace::Linear).w
    }
}

impl HitFilter for AlphaMask {
    const FILTERS: bool = true;

    /// Kept where alpha ≥ cutoff (glTF: "fully opaque" there, "fully transparent" below). A NaN
    /// alpha (none arises: texture lookups and the factor are finite) would cut the hit out.
    #[inline]
    fn keeps(&self, triangle: u32, b1: f32, b2: f32) -> bool {
        let material = self.material_of_triangle[triangle as usize] as usize;
        match &self.cutouts[material] {
            None => true,
            Some(cutout) => self.alpha(cutout, triangle, b1, b2) >= cutout.cutoff,
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::material::{BrdfModel, Cutout};
    use crate::texture::{Filter, Wrap};

    /// One triangle with u running 0 → 1 from vertex 0 to vertex 1, material `material`.
    fn mesh(material: u32) -> TriangleMesh {
        TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: vec![Vec3::Z; 3],
            uvs: Some(vec![Vec2::new(0.0, 0.5), Vec2::new(1.0, 0.5), Vec2::new(0.0, 0.5)]),
            triangles: vec![[0, 1, 2]],
            material_of_triangle: vec![material],
            ..TriangleMesh::default()
        }
    }

    fn masked(alpha: f32, texture: bool) -> Material {
        let mut m = Material::gltf_pbr("leaf", [1.0; 3], 0.0, 1.0);
        if let BrdfModel::GltfPbr(p) = &mut m.model {
            p.cutout = Some(Cutout { cutoff: 0.5, alpha });
            m.textures.base_color = texture.then_some(TextureRef {
                image: 1,
                tex_coord: 0,
                wrap_u: Wrap::ClampToEdge,
                wrap_v: Wrap::ClampToEdge,
                filter: Filter::Nearest,
                transform: None,
            });
        }
        m
    }

    /// Image 1: two texels, alpha 0 on the left half, 255 on the right.
    fn images() -> Vec<TextureImage> {
        let image = |label: &str, texels| TextureImage {
            label: label.into(),
            width: 2,
            height: 1,
            texels,
        };
        vec![
            image("unused", vec![[0; 4]; 2]),
            image("alpha", vec![[200, 200, 200, 0], [200, 200, 200, 255]]),
        ]
    }

    #[test]
    fn scenes_without_a_used_cutout_have_no_mask() {
        let opaque = Material::gltf_pbr("opaque", [1.0; 3], 0.0, 1.0);
        assert!(AlphaMask::new(&mesh(0), std::slice::from_ref(&opaque), &images()).is_none());
        // A masked material no triangle uses does not count either.
        assert!(AlphaMask::new(&mesh(0), &[opaque, masked(0.0, false)], &images()).is_none());
    }

    #[test]
    fn the_factor_alone_cuts_everything_or_nothing() {
        let cut = AlphaMask::new(&mesh(0), &[masked(0.4, false)], &images()).unwrap();
        assert!(!cut.keeps(0, 0.3, 0.3));
        let kept = AlphaMask::new(&mesh(0), &[masked(0.5, false)], &images()).unwrap();
        assert!(kept.keeps(0, 0.3, 0.3), "alpha = cutoff is opaque");
    }

    #[test]
    fn the_texture_alpha_cuts_where_it_is_below_the_cutoff() {
        let mask = AlphaMask::new(&mesh(0), &[masked(1.0, true)], &images()).unwrap();
        assert_eq!(mask.images.len(), 1, "only the image the cut-out reads is kept");
        // b1 is u here: the left texel (alpha 0) below u = 0.5, the right (alpha 1) above.
        assert!(!mask.keeps(0, 0.2, 0.1));
        assert!(mask.keeps(0, 0.8, 0.1));
        // The factor scales the texture's alpha: 0.4 × 1 < 0.5.
        let faint = AlphaMask::new(&mesh(0), &[masked(0.4, true)], &images()).unwrap();
        assert!(!faint.keeps(0, 0.8, 0.1));
    }
}
