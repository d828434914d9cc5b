//! How shadow rays leave a surface: the choices a scene file or the command line makes. The
//! offsets themselves are computed in [`crate::accel::shadow`].

/// How shadow-ray origins leave the surface.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ShadowOffset {
    /// pointshade's default: the error-bound offset of [`offset_origin`](crate::accel::shadow::offset_origin), correct at any scale.
    #[default]
    ErrorBound,
    /// Mitsuba 3's fixed epsilon, for pixel-exact validation: the origin moves along the
    /// geometric normal by (1 + max|p_k|)·2⁻²⁴·1500 and the ray stops at (1 − 10·that epsilon)
    /// of the distance to the light. It loses contact shadows far from the origin and shows the
    /// "shadow terminator" on coarse smooth meshes, exactly as Mitsuba does.
    Mitsuba,
}

impl ShadowOffset {
    /// Every name [`ShadowOffset::parse`] knows.
    pub const NAMES: &'static [&'static str] = &["error-bound", "mitsuba"];

    /// Name in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::ErrorBound => "error-bound",
            Self::Mitsuba => "mitsuba",
        }
    }

    /// Parses a name; the error lists the valid ones.
    pub fn parse(name: &str) -> Result<Self, String> {
        match name {
            "error-bound" => Ok(Self::ErrorBound),
            "mitsuba" => Ok(Self::Mitsuba),
            other => Err(format!(
                "unknown shadow offset '{other}' (expected error-bound or mitsuba)"
            )),
        }
    }
}

/// Where shadow rays start on a mesh whose vertex normals bend away from its flat triangles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ShadowTerminator {
    /// pointshade's default: from the point moved onto the smooth surface of the vertex normals
    /// (`surface::primary::smooth_origin`), so that a coarse smooth-shaded mesh does not shadow
    /// itself in facets where its shading turns towards the light.
    #[default]
    Smooth,
    /// From the hit point on the flat triangle: the geometry as it is, facets and all. The
    /// `mitsuba` offset always starts there, as Mitsuba does.
    Flat,
}

impl ShadowTerminator {
    /// Every name [`ShadowTerminator::parse`] knows.
    pub const NAMES: &'static [&'static str] = &["smooth", "flat"];

    /// Name in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Smooth => "smooth",
            Self::Flat => "flat",
        }
    }

    /// Parses a name; the error lists the valid ones.
    pub fn parse(name: &str) -> Result<Self, String> {
        match name {
            "smooth" => Ok(Self::Smooth),
            "flat" => Ok(Self::Flat),
            other => Err(format!("unknown shadow terminator '{other}' (expected smooth or flat)")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_back_and_unknown_names_are_refused() {
        for o in [ShadowOffset::ErrorBound, ShadowOffset::Mitsuba] {
            assert_eq!(ShadowOffset::parse(o.name()), Ok(o));
        }
        let names = |n: &[&str]| n.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        assert_eq!(names(ShadowOffset::NAMES), ["error-bound", "mitsuba"]);
        assert_eq!(names(ShadowTerminator::NAMES), ["smooth", "flat"]);
        assert!(ShadowOffset::parse("fixed").is_err());
        for t in [ShadowTerminator::Smooth, ShadowTerminator::Flat] {
            assert_eq!(ShadowTerminator::parse(t.name()), Ok(t));
        }
        assert!(ShadowTerminator::parse("soft").is_err());
    }
}
