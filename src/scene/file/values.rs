//! Values of a scene file: paths relative to it, points (rebased to the scene origin) and vectors.

use std::path::{Path, PathBuf};

use glam::{DVec3, Vec3};
use serde::de::{Deserialize, Deserializer, Error};

/// A vector of exactly three numbers: serde reads a `[T; 3]` from the first three elements of
/// a TOML array and ignores the rest, so `position = [0, 2.2, 5.5, "junk"]` would be accepted.
/// For `#[serde(deserialize_with = "three")]`.
pub(crate) fn three<'de, D: Deserializer<'de>, T: Deserialize<'de>>(d: D) -> Result<[T; 3], D::Error> {
    let elements = Vec::<T>::deserialize(d)?;
    let count = elements.len();
    <[T; 3]>::try_from(elements).map_err(|_| D::Error::invalid_length(count, &"3 numbers"))
}

/// [`three`] for an optional key (with `#[serde(default, deserialize_with = "three_opt")]`).
pub(crate) fn three_opt<'de, D: Deserializer<'de>, T: Deserialize<'de>>(d: D) -> Result<Option<[T; 3]>, D::Error> {
    three(d).map(Some)
}

/// `file` relative to the directory `dir` of the scene file (absolute paths unchanged).
pub(crate) fn resolve(dir: &Path, file: &str) -> PathBuf {
    let p = Path::new(file);
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        dir.join(p)
    }
}

/// A finite vector, or an error naming the key.
/// A position read in f64, relative to the scene's `origin`, in f32 (finite in both).
pub(crate) fn point3(name: &str, v: [f64; 3], origin: DVec3) -> Result<Vec3, String> {
    let p = DVec3::from(v);
    let local = (p - origin).as_vec3();
    if p.is_finite() && local.is_finite() {
        Ok(local)
    } else {
        Err(format!("{name} must be finite, got {p}"))
    }
}

pub(crate) fn vec3(name: &str, v: [f32; 3]) -> Result<Vec3, String> {
    let v = Vec3::from(v);
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("{name} must be finite, got {v}"))
    }
}
