//! The pieces of Mitsuba scene XML that the scene export and the texture export both write.

use glam::Vec3;

pub(super) fn rgb(name: &str, c: [f32; 3]) -> String {
    format!("<rgb name=\"{name}\" value=\"{}, {}, {}\"/>", c[0], c[1], c[2])
}

pub(super) fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A vector as Mitsuba's attributes write one: `x, y, z`.
pub(super) fn v3(v: Vec3) -> String {
    format!("{}, {}, {}", v.x, v.y, v.z)
}
