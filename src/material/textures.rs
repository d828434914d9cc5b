//! A material's textures, for every model in one place, and what each modulates (the
//! material's BRDF at a point once they are applied is [`crate::material::PointBrdf`]).
//!
//! | texture | from | modulates |
//! |---|---|---|
//! | `base_color` (sRGB) | glTF `baseColorTexture`, MTL `map_Kd` | the albedo / base colour; its alpha the cut-out's |
//! | `metallic_roughness` (linear) | glTF `metallicRoughnessTexture` | `gltf-pbr`: blue × metallic, green × roughness |
//! | `specular` (sRGB) | MTL `map_Ks` | Blinn-Phong's and Cook-Torrance's specular colour |
//! | `shininess` (one channel) | MTL `map_Ns` | Blinn-Phong's exponent: Ns × value |
//! | `roughness` (one channel) | MTL `map_Pr` | Cook-Torrance: α = (Pr × value)² |
//! | `metallic` (one channel) | MTL `map_Pm` | Cook-Torrance: a metal where Pm × value ≥ 0.5 |
//! | `normal` (linear) | glTF `normalTexture`, MTL `norm`/`map_Bump` | the shading normal, in the surface stage |
//! | `emissive` (sRGB) | glTF `emissiveTexture` | the emissive factor |

use glam::Vec2;

use crate::texture::{ColorSpace, TextureImage, TextureRef};

/// A tangent-space normal texture (+X along +u, +Y "up" = against +v, +Z out of the surface),
/// whose X and Y are multiplied by `scale` (glTF `normalTexture.scale`, MTL `-bm`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalTexture {
    /// The texture (linear).
    pub texture: TextureRef,
    /// Multiplies the decoded X and Y.
    pub scale: f32,
}

/// Which channel of an image a one-channel texture reads (MTL `-imfchan`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Channel {
    /// Red.
    R,
    /// Green.
    G,
    /// Blue.
    B,
    /// Alpha (`m`, the matte channel).
    A,
    /// Luminance 0.2126 R + 0.7152 G + 0.0722 B of the linear values (MTL's default for
    /// scalar textures); a grey image reads its grey.
    #[default]
    Luminance,
}

/// A one-channel texture and the factor its value multiplies (the MTL statement's scalar, e.g.
/// `Ns` for `map_Ns`): the parameter at a point is `factor × value`, value in [0, 1].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScalarTexture {
    /// The texture (linear).
    pub texture: TextureRef,
    /// The channel read.
    pub channel: Channel,
    /// What the value multiplies.
    pub factor: f32,
}

impl ScalarTexture {
    /// `factor × value` at texture coordinates `uvs` (sets 0 and 1).
    #[inline]
    pub fn at(&self, uvs: [Vec2; 2], images: &[TextureImage]) -> f32 {
        let t = self
            .texture
            .sample(images, uvs[self.texture.tex_coord as usize], ColorSpace::Linear);
        let value = match self.channel {
            Channel::R => t.x,
            Channel::G => t.y,
            Channel::B => t.z,
            Channel::A => t.w,
            Channel::Luminance => 0.2126 * t.x + 0.7152 * t.y + 0.0722 * t.z,
        };
        self.factor * value
    }
}

/// A material's textures; each is optional (see the module's table).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MaterialTextures {
    /// sRGB; RGB multiplies the albedo (the base colour factor), alpha the cut-out's alpha.
    pub base_color: Option<TextureRef>,
    /// Linear; blue multiplies a `gltf-pbr` material's metallic factor, green its roughness.
    pub metallic_roughness: Option<TextureRef>,
    /// sRGB; multiplies the specular colour.
    pub specular: Option<TextureRef>,
    /// Blinn-Phong's exponent.
    pub shininess: Option<ScalarTexture>,
    /// Cook-Torrance's perceptual roughness (α = value²).
    pub roughness: Option<ScalarTexture>,
    /// Cook-Torrance's metalness (a metal where the value is ≥ 0.5).
    pub metallic: Option<ScalarTexture>,
    /// Tangent-space normals; applied by the surface stage (`surface::normal_texture`).
    pub normal: Option<NormalTexture>,
    /// sRGB; multiplies the emissive factor.
    pub emissive: Option<TextureRef>,
}

impl MaterialTextures {
    /// Whether a texture changes the BRDF's parameters (all but the normal and emissive ones).
    pub fn varies_brdf(&self) -> bool {
        self.base_color.is_some()
            || self.metallic_roughness.is_some()
            || self.specular.is_some()
            || self.shininess.is_some()
            || self.roughness.is_some()
            || self.metallic.is_some()
    }

    /// Every texture reference, for renumbering images (a copy of the textures, which are
    /// `Copy`, lists them without changing the material).
    pub fn refs_mut(&mut self) -> impl Iterator<Item = &mut TextureRef> {
        [
            self.base_color.as_mut(),
            self.metallic_roughness.as_mut(),
            self.specular.as_mut(),
            self.shininess.as_mut().map(|s| &mut s.texture),
            self.roughness.as_mut().map(|s| &mut s.texture),
            self.metallic.as_mut().map(|s| &mut s.texture),
            self.normal.as_mut().map(|n| &mut n.texture),
            self.emissive.as_mut(),
        ]
        .into_iter()
        .flatten()
    }
}
