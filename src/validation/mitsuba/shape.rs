//! Shapes: a single-material OBJ referenced with its transform (`obj`), or a world-space PLY
//! part written beside the XML (`ply`), each with its BSDF and, in the emission pass, its
//! `area` emitter.

use std::path::Path;

use glam::Mat4;

use crate::validation::xml::xml_escape;

/// A PLY part of the scene mesh, already in world space, by its file name beside the XML.
pub(super) fn ply_shape(name: &str, material: u32, emitter: Option<&str>) -> String {
    format!(
        "  <shape type=\"ply\">\n    <string name=\"filename\" value=\"{}\"/>\n    <ref id=\"mat{material}\"/>\n{}  </shape>",
        xml_escape(name),
        emitter_line(emitter)
    )
}

fn emitter_line(emitter: Option<&str>) -> String {
    emitter.map_or_else(String::new, |e| format!("    {e}\n"))
}

/// An OBJ file as Mitsuba reads it, placed by `transform`.
pub(super) fn shape(mesh: &Path, transform: Mat4, material: u32, emitter: Option<&str>) -> String {
    let path = std::fs::canonicalize(mesh).unwrap_or_else(|_| mesh.to_path_buf());
    let m = transform.transpose().to_cols_array(); // row-major
    let matrix = m.iter().map(|v| v.to_string()).collect::<Vec<_>>().join(" ");
    format!(
        "  <shape type=\"obj\">\n    <string name=\"filename\" value=\"{}\"/>\n    <transform name=\"to_world\"><matrix value=\"{matrix}\"/></transform>\n    <ref id=\"mat{material}\"/>\n{}  </shape>",
        xml_escape(&path.display().to_string()),
        emitter_line(emitter)
    )
}
