//! Cameras: film coordinates → primary rays.
//!
//! The perspective ray is exactly Mitsuba 3's `perspective` sensor (see
//! `shared/notes/mitsuba3.md` §3.2): local frame x = left, y = up, z = forward from `look_at`,
//! `d_local = normalize((1 − 2u)·t, (1 − 2v)·t/a, 1)` with `t = tan(x_fov/2)`, `a = W/H`, and the
//! origin moved to the near plane. Row 0 is the top of the image; (u, v) ∈ [0, 1)².

use glam::Vec3;

use crate::lanes::{dot3, map3, Real};

/// Which image axis `fov` spans.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FovAxis {
    /// Horizontal field of view (Mitsuba's default).
    X,
    /// Vertical field of view (pointshade's default).
    Y,
}

/// How rays leave the camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Pinhole: `fov` in degrees across `fov_axis`.
    Perspective { fov_degrees: f32, fov_axis: FovAxis },
    /// Parallel rays; `scale` is half the image height in scene units.
    Orthographic { scale: f32 },
}

/// A camera as a scene describes it, independent of the image resolution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraSpec {
    /// Eye position.
    pub position: Vec3,
    /// A point the camera looks at.
    pub look_at: Vec3,
    /// Approximate up direction (need not be orthogonal to the view direction).
    pub up: Vec3,
    /// Projection.
    pub projection: Projection,
    /// Distance along the view axis where rays start (Mitsuba's `near_clip`); 0 = at the eye.
    pub near_clip: f32,
    /// Distance along the view axis where rays end; infinity = unbounded.
    pub far_clip: f32,
}

/// A primary ray in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraRay {
    /// Start of the ray.
    pub origin: Vec3,
    /// Unit direction.
    pub direction: Vec3,
    /// Largest distance along `direction` that counts as a hit.
    pub t_max: f32,
}

/// Rays of [`Camera::rays`], one per lane of `R`: each coordinate in the lanes of `R`.
#[derive(Clone, Copy, Debug)]
pub struct CameraRays<R> {
    /// Starts of the rays, per axis.
    pub origin: [R; 3],
    /// Unit directions, per axis.
    pub direction: [R; 3],
    /// Largest distances along `direction` that count as a hit.
    pub t_max: R,
}

/// A camera bound to an image size, with its frame precomputed.
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    spec: CameraSpec,
    left: Vec3,
    up: Vec3,
    forward: Vec3,
    /// Half extents of the image plane: perspective at z = 1, orthographic in scene units.
    half_x: f32,
    half_y: f32,
}

impl Camera {
    /// Builds the camera frame as Mitsuba's `look_at` does: `dir = normalize(target − origin)`,
    /// `left = normalize(cross(up, dir))`, `up' = cross(dir, left)`. Errors describe a degenerate
    /// frame or projection in words fit for the user.
    pub fn new(spec: CameraSpec, width: u32, height: u32) -> Result<Self, String> {
        let forward = (spec.look_at - spec.position).normalize_or_zero();
        if forward == Vec3::ZERO || !forward.is_finite() {
            return Err("camera position and look_at must differ".into());
        }
        let left = spec.up.cross(forward).normalize_or_zero();
        if left == Vec3::ZERO || !left.is_finite() {
            return Err("camera up is parallel to the view direction (or zero)".into());
        }
        let up = forward.cross(left);
        let aspect = width as f32 / height as f32;
        let (half_x, half_y) = match spec.projection {
            Projection::Perspective { fov_degrees, fov_axis } => {
                if !(fov_degrees > 0.0 && fov_degrees < 180.0) {
                    return Err(format!("fov must be in (0, 180) degrees, got {fov_degrees}"));
                }
                let t = (fov_degrees.to_radians() * 0.5).tan();
                match fov_axis {
                    FovAxis::X => (t, t / aspect),
                    FovAxis::Y => (t * aspect, t),
                }
            }
            Projection::Orthographic { scale } => {
                if !(scale > 0.0 && scale.is_finite()) {
                    return Err(format!("orthographic scale must be > 0, got {scale}"));
                }
                (scale * aspect, scale)
            }
        };
        if !(spec.near_clip >= 0.0 && spec.far_clip > spec.near_clip) {
            return Err(format!(
                "clip range must satisfy 0 ≤ near_clip < far_clip, got {} and {}",
                spec.near_clip, spec.far_clip
            ));
        }
        Ok(Self {
            spec,
            left,
            up,
            forward,
            half_x,
            half_y,
        })
    }

    /// The ray through film point (u, v) ∈ [0, 1)², u to the right, v downwards.
    #[inline]
    pub fn ray(&self, u: f32, v: f32) -> CameraRay {
        let r = self.rays(u, v);
        CameraRay {
            origin: Vec3::from_array(r.origin),
            direction: Vec3::from_array(r.direction),
            t_max: r.t_max,
        }
    }

    /// [`Camera::ray`] of the film points in the lanes of `u` and `v` (one in a scalar, eight
    /// in [`F32x8`](crate::lanes::F32x8)): the same operations lane by lane, as glam's `Vec3`
    /// arithmetic does them per component, so every lane is the single ray to the bit.
    #[inline(always)]
    pub fn rays<R: Real>(&self, u: R, v: R) -> CameraRays<R> {
        let sx = R::one() - R::lit(2.0) * u; // along `left`
        let sy = R::one() - R::lit(2.0) * v; // along `up`
        let axis = |a: Vec3| map3(a.to_array(), R::of);
        let (left, up, forward, position) = (
            axis(self.left),
            axis(self.up),
            axis(self.forward),
            axis(self.spec.position),
        );
        let (near_clip, depth) = (self.spec.near_clip, self.spec.far_clip - self.spec.near_clip);
        match self.spec.projection {
            Projection::Perspective { .. } => {
                let local = [sx * R::of(self.half_x), sy * R::of(self.half_y), R::one()];
                let inv_length = dot3(local, local).sqrt().recip();
                let local = map3(local, |c| c * inv_length);
                let direction = map3([0, 1, 2], |c| {
                    local[0] * left[c] + local[1] * up[c] + local[2] * forward[c]
                });
                let near = R::of(near_clip) / local[2];
                CameraRays {
                    origin: map3([0, 1, 2], |c| position[c] + direction[c] * near),
                    direction,
                    t_max: R::of(depth) / local[2],
                }
            }
            Projection::Orthographic { .. } => {
                let (x, y) = (sx * R::of(self.half_x), sy * R::of(self.half_y));
                let near = R::of(near_clip);
                CameraRays {
                    origin: map3([0, 1, 2], |c| position[c] + x * left[c] + y * up[c] + near * forward[c]),
                    direction: forward,
                    t_max: R::of(depth),
                }
            }
        }
    }

    /// The scene-level description this camera was built from.
    pub fn spec(&self) -> &CameraSpec {
        &self.spec
    }

    /// Unit view direction.
    pub fn forward(&self) -> Vec3 {
        self.forward
    }

    /// The camera's orthonormal frame (left, up, forward), as Mitsuba's `look_at` builds it.
    pub fn frame(&self) -> (Vec3, Vec3, Vec3) {
        (self.left, self.up, self.forward)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(projection: Projection) -> CameraSpec {
        CameraSpec {
            position: Vec3::new(1.0, 2.0, 3.0),
            look_at: Vec3::new(1.0, 2.0, 4.0),
            up: Vec3::Y,
            projection,
            near_clip: 0.01,
            far_clip: 1e4,
        }
    }

    /// The ray as glam's `Vec3` arithmetic writes it (what `Camera::ray` computed before it had
    /// lanes): the reference for the bits of every lane.
    fn glam_ray(c: &Camera, u: f32, v: f32) -> CameraRay {
        let (sx, sy) = (1.0 - 2.0 * u, 1.0 - 2.0 * v);
        let s = &c.spec;
        match s.projection {
            Projection::Perspective { .. } => {
                let local = Vec3::new(sx * c.half_x, sy * c.half_y, 1.0).normalize();
                let direction = local.x * c.left + local.y * c.up + local.z * c.forward;
                let near = s.near_clip / local.z;
                CameraRay {
                    origin: s.position + direction * near,
                    direction,
                    t_max: (s.far_clip - s.near_clip) / local.z,
                }
            }
            Projection::Orthographic { .. } => CameraRay {
                origin: s.position + sx * c.half_x * c.left + sy * c.half_y * c.up + s.near_clip * c.forward,
                direction: c.forward,
                t_max: s.far_clip - s.near_clip,
            },
        }
    }

    #[test]
    fn rays_in_lanes_are_the_single_rays_to_the_bit() {
        use crate::lanes::F32x8;
        let projections = [
            Projection::Perspective {
                fov_degrees: 39.3,
                fov_axis: FovAxis::X,
            },
            Projection::Perspective {
                fov_degrees: 70.0,
                fov_axis: FovAxis::Y,
            },
            Projection::Orthographic { scale: 2.5 },
        ];
        let mut random = crate::test_random::XorShift32::new(0x2545_f491);
        for projection in projections {
            for far_clip in [1e4, f32::INFINITY] {
                let spec = CameraSpec {
                    position: Vec3::new(-3.7, 12.25, 0.3),
                    look_at: Vec3::new(0.4, -1.0, 2.0),
                    far_clip,
                    ..spec(projection)
                };
                let camera = Camera::new(spec, 640, 360).unwrap();
                for _ in 0..200 {
                    let (mut u, mut v) = (F32x8::splat(0.0), F32x8::splat(0.0));
                    for i in 0..8 {
                        (u.0[i], v.0[i]) = (random.unit(), random.unit());
                    }
                    let lanes = camera.rays(u, v);
                    for i in 0..8 {
                        let want = glam_ray(&camera, u.0[i], v.0[i]);
                        let bits = |r: CameraRay| {
                            (
                                r.origin.to_array().map(f32::to_bits),
                                r.direction.to_array().map(f32::to_bits),
                                r.t_max.to_bits(),
                            )
                        };

                        let got = CameraRay {
                            origin: crate::lanes::lane_vec3(&lanes.origin, i),
                            direction: crate::lanes::lane_vec3(&lanes.direction, i),
                            t_max: lanes.t_max.0[i],
                        };
                        assert_eq!(bits(got), bits(want), "{projection:?} at ({}, {})", u.0[i], v.0[i]);
                        assert_eq!(bits(camera.ray(u.0[i], v.0[i])), bits(want));
                    }
                }
            }
        }
    }

    /// Mitsuba's formula written out independently in f64 (mitsuba3.md §3.2).
    fn mitsuba_ray(s: &CameraSpec, x_fov_deg: f64, w: f64, h: f64, u: f64, v: f64) -> ([f64; 3], [f64; 3]) {
        let t = (x_fov_deg.to_radians() / 2.0).tan();
        let a = w / h;
        let (lx, ly, lz) = ((1.0 - 2.0 * u) * t, (1.0 - 2.0 * v) * t / a, 1.0);
        let len = (lx * lx + ly * ly + lz * lz).sqrt();
        let (lx, ly, lz) = (lx / len, ly / len, lz / len);
        // Camera looks along +Z with up +Y: left = cross(up, dir) = +X.
        let d = [lx, ly, lz];
        let near = s.near_clip as f64 / lz;
        let o = [1.0 + d[0] * near, 2.0 + d[1] * near, 3.0 + d[2] * near];
        (o, d)
    }

    #[test]
    fn perspective_ray_matches_mitsuba_formula_with_horizontal_fov() {
        let s = spec(Projection::Perspective {
            fov_degrees: 40.0,
            fov_axis: FovAxis::X,
        });
        let cam = Camera::new(s, 320, 200).unwrap();
        for &(px, py) in &[(0.5, 0.5), (319.5, 199.5), (160.0, 100.0), (12.25, 180.75)] {
            let (u, v) = (px / 320.0, py / 200.0);
            let r = cam.ray(u as f32, v as f32);
            let (o, d) = mitsuba_ray(&s, 40.0, 320.0, 200.0, u, v);
            for k in 0..3 {
                assert!((r.direction[k] as f64 - d[k]).abs() < 1e-6, "{r:?} vs {d:?}");
                assert!((r.origin[k] as f64 - o[k]).abs() < 1e-6, "{r:?} vs {o:?}");
            }
        }
    }

    #[test]
    fn vertical_fov_converts_to_mitsuba_horizontal_fov() {
        let s = spec(Projection::Perspective {
            fov_degrees: 30.0,
            fov_axis: FovAxis::Y,
        });
        let cam = Camera::new(s, 400, 100).unwrap();
        let x_fov = 2.0 * ((15f64).to_radians().tan() * 4.0).atan();
        let r = cam.ray(0.1, 0.9);
        let (_, d) = mitsuba_ray(&s, x_fov.to_degrees(), 400.0, 100.0, 0.1, 0.9);
        for (k, expected) in d.iter().enumerate() {
            assert!((r.direction[k] as f64 - expected).abs() < 1e-6);
        }
    }

    #[test]
    fn row_zero_is_the_top_and_column_zero_the_left() {
        let s = spec(Projection::Perspective {
            fov_degrees: 60.0,
            fov_axis: FovAxis::Y,
        });
        let cam = Camera::new(s, 100, 100).unwrap();
        let top_left = cam.ray(0.0, 0.0).direction;
        // Looking along +Z with +Y up, the right of the picture is −X (left = +X).
        assert!(top_left.y > 0.0 && top_left.x > 0.0);
    }

    #[test]
    fn orthographic_rays_are_parallel_and_span_scale() {
        let s = spec(Projection::Orthographic { scale: 2.0 });
        let cam = Camera::new(CameraSpec { near_clip: 0.0, ..s }, 200, 100).unwrap();
        let top = cam.ray(0.5, 0.0);
        assert_eq!(top.direction, Vec3::Z);
        assert!((top.origin - Vec3::new(1.0, 4.0, 3.0)).length() < 1e-6);
        let left_edge = cam.ray(0.0, 0.5);
        assert!((left_edge.origin - Vec3::new(5.0, 2.0, 3.0)).length() < 1e-6);
    }

    #[test]
    fn degenerate_frames_are_errors() {
        let mut s = spec(Projection::Perspective {
            fov_degrees: 40.0,
            fov_axis: FovAxis::Y,
        });
        s.up = Vec3::Z;
        assert!(Camera::new(s, 10, 10).unwrap_err().contains("parallel"));
        s.up = Vec3::Y;
        s.look_at = s.position;
        assert!(Camera::new(s, 10, 10).is_err());
        s.look_at = Vec3::ZERO;
        s.projection = Projection::Perspective {
            fov_degrees: f32::NAN,
            fov_axis: FovAxis::Y,
        };
        assert!(Camera::new(s, 10, 10).is_err());
    }
}
