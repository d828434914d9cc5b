use super::*;

/// `n` triangles of radius `radius` around `offset`, as an OBJ polygon of n + 1 vertices
/// triangulates.
fn fan(n: usize, offset: Vec3, radius: f32) -> TriangleMesh {
    let mut positions = vec![offset];
    positions.extend((0..=n).map(|k| {
        let a = std::f32::consts::PI * k as f32 / n as f32;
        offset + radius * Vec3::new(a.cos(), a.sin(), 0.0)
    }));
    TriangleMesh {
        normals: vec![Vec3::Z; positions.len()],
        positions,
        triangles: (0..n as u32).map(|k| [0, k + 1, k + 2]).collect(),
        material_of_triangle: vec![0; n],
        ..Default::default()
    }
}

#[test]
fn fans_build_balanced_trees_and_are_hit_where_they_are() {
    // PLOC built a chain about 600 levels deep for 30,000 triangles, in time quadratic in
    // their count, and its collapse overflowed the stack.
    // The radius 5.7e27 is the geometry fuzz target's finding (fuzz/README.md): the f32
    // diagonal overflowed, the scene stayed at scale 1 with boxes of infinite area, and the
    // window test could not see the fan.
    for (offset, radius) in [
        (Vec3::ZERO, 1.0),
        (Vec3::new(9.2e18, 0.0, 0.0), 1.0),
        (Vec3::ZERO, 5.7e27),
    ] {
        let mesh = fan(30_000, offset, radius);
        // The default (binned SAH) and PLOC with its balanced fallback.
        for preset in [BvhPreset::DEFAULT, BvhPreset::Fast] {
            let bvh = Bvh::build(&mesh, preset);
            let depth = bvh.depth();
            assert!(
                depth <= 12,
                "{preset:?}: depth {depth} at offset {offset}, radius {radius:e}"
            );
            if offset == Vec3::ZERO && radius == 1.0 {
                let hit = bvh.intersect(Vec3::new(0.3, 0.4, 1.0), Vec3::NEG_Z, f32::INFINITY);
                assert!(hit.is_some_and(|h| (h.t - 1.0).abs() < 1e-5), "{preset:?}: {hit:?}");
            }
        }
    }
}

#[test]
fn a_fan_of_subnormal_size_builds() {
    // The geometry fuzz target's third finding: a scale of 2^133 was infinite, and obvhs's
    // PLOC indexed with −1 on the boxes it made.
    for preset in [BvhPreset::DEFAULT, BvhPreset::Fast] {
        let bvh = Bvh::build(&fan(160, Vec3::ZERO, 1.1755033e-38), preset);
        assert!(bvh.depth() <= 64 && bvh.scene_unit().is_finite(), "{preset:?}");
    }
}

fn quad(y: f32, half: f32, offset: Vec3) -> TriangleMesh {
    let p = [
        Vec3::new(-half, y, -half),
        Vec3::new(half, y, -half),
        Vec3::new(half, y, half),
        Vec3::new(-half, y, half),
    ]
    .map(|v| v + offset);
    TriangleMesh {
        positions: p.to_vec(),
        normals: vec![Vec3::Y; 4],
        triangles: vec![[0, 2, 1], [0, 3, 2]],
        material_of_triangle: vec![0, 0],
        ..Default::default()
    }
}

#[test]
fn triangles_without_area_are_left_out_unless_nothing_else_is_left() {
    let stored = |bvh: &Bvh| {
        let mut p: Vec<u32> = bvh
            .wide
            .quad_triangles
            .iter()
            .flatten()
            .copied()
            .filter(|&p| p != wide::EMPTY)
            .collect();
        p.sort_unstable();
        p
    };
    // Triangle 1 repeats a vertex and triangle 3 has collinear vertices.
    let mut mesh = quad(0.0, 1.0, Vec3::ZERO);
    mesh.positions.push(Vec3::new(3.0, 0.0, -1.0)); // on the line through vertices 0 and 1
    mesh.triangles = vec![[0, 2, 1], [0, 0, 2], [0, 3, 2], [0, 1, 4]];
    mesh.material_of_triangle = vec![0; 4];
    let bvh = Bvh::build(&mesh, BvhPreset::DEFAULT);
    assert_eq!(stored(&bvh), [0, 2]);
    // The degenerate ones alone: kept, so that the tree is not empty.
    mesh.triangles = vec![[0, 0, 2], [0, 1, 4]];
    mesh.material_of_triangle = vec![0; 2];
    assert_eq!(stored(&Bvh::build(&mesh, BvhPreset::DEFAULT)), [0, 1]);
}

#[test]
fn closest_hit_and_occlusion_at_any_scale_and_offset() {
    for &(size, offset) in &[(1.0f32, 0.0f32), (1e-6, 0.0), (1e6, 0.0), (1.0, 1e5)] {
        let off = Vec3::splat(offset);
        let mut mesh = quad(0.0, size, off);
        mesh.append(quad(size, size, off), 0);
        let bvh = Bvh::build(&mesh, BvhPreset::DEFAULT);
        let from = off + Vec3::new(0.1, 3.0, 0.2) * size;
        let hit = bvh.intersect(from, Vec3::NEG_Y, f32::INFINITY).expect("hit");
        assert!(hit.triangle >= 2, "upper quad first (size {size})");
        assert!(
            (hit.t - 2.0 * size).abs() <= 1e-4 * size + offset * 1e-6,
            "t {} size {size}",
            hit.t
        );
        assert!(bvh.any_hit(from, Vec3::NEG_Y, 10.0 * size));
        assert!(!bvh.any_hit(from, Vec3::NEG_Y, 1.5 * size), "t_max respected");
        assert!(!bvh.any_hit(from, Vec3::Y, f32::INFINITY));
    }
}

#[test]
fn point_under_a_plane_is_in_shadow_and_a_point_on_it_is_not() {
    for &offset in &[0.0f32, 1e5] {
        let off = Vec3::splat(offset);
        let bvh = Bvh::build(&quad(0.0, 4.0, off), BvhPreset::DEFAULT);
        let light = off + Vec3::new(0.3, 5.0, -0.2);
        let unit = bvh.scene_unit();
        let ray_to_light = |p: Vec3, ng: Vec3| {
            let to = light - p;
            ShadowRay::towards_light(p, ng, to.normalize(), to.length(), unit)
        };
        // Under the plane: occluded, down to depths of 1e-3 of the plane's size or 16 ulps of
        // the coordinates (0.125 at 1e5), whichever is larger; closer than that a point cannot
        // be told from one on the plane in f32.
        let ulp16 = 16.0 * (offset.max(1.0) * f32::EPSILON);
        for depth in [1.0f32, 1e-1, 1e-2, 1e-3].into_iter().filter(|&d| d >= ulp16) {
            let under = off + Vec3::new(-0.4, -depth, 0.7);
            assert!(
                bvh.occluded(&ray_to_light(under, Vec3::NEG_Y)),
                "offset {offset}, {depth} below"
            );
        }
        // On the plane, computed from barycentrics as the renderer does: lit, everywhere.
        let mesh = quad(0.0, 4.0, off);
        for k in 0..100 {
            let (b1, b2) = ((k % 10) as f32 / 10.0 * 0.9, (k / 10) as f32 / 10.0 * 0.09);
            let [p0, p1, p2] = mesh.triangle_positions(k % 2);
            let on = (1.0 - b1 - b2) * p0 + b1 * p1 + b2 * p2;
            assert!(
                !bvh.occluded(&ray_to_light(on, Vec3::Y)),
                "offset {offset}: acne at {on}"
            );
        }
    }
}

#[test]
fn directions_with_negative_zero_components_find_their_hits() {
    // A quad in the plane z = 2, off the axis so the ray starts beside it in x; directions
    // with −0.0 components (e.g. the negation of a light's direction) must hit as +0.0 does.
    let mut mesh = quad(0.0, 1.0, Vec3::ZERO);
    mesh.transform(glam::Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2));
    mesh.append(quad(-3.0, 5.0, Vec3::ZERO), 0); // a large floor so the BVH has several nodes
    let bvh = Bvh::build(&mesh, BvhPreset::DEFAULT);
    for d in [
        Vec3::new(-0.0, -0.0, 1.0),
        Vec3::new(-0.0, 0.0, -1.0),
        Vec3::new(0.3, -0.0, 0.9).normalize(),
    ] {
        let from = Vec3::new(0.2, 0.1, 0.0) - d * 5.0;
        let plus = Vec3::new(d.x + 0.0, d.y + 0.0, d.z + 0.0);
        assert_eq!(bvh.intersect(from, d, 100.0), bvh.intersect(from, plus, 100.0), "{d:?}");
        assert!(bvh.any_hit(from, d, 100.0), "{d:?}");
    }
}

/// The torus with every triangle listed twice (the copies, at index + n, coincide exactly).
fn doubled_torus() -> (TriangleMesh, u32) {
    let mut mesh = crate::scene::procedural::torus(1.0, 0.35, 64, 24).into_triangle_mesh();
    let n = mesh.triangle_count();
    mesh.append(mesh.clone(), 0);
    (mesh, n as u32)
}

#[test]
fn coincident_triangles_resolve_to_the_lower_index_in_every_tree_and_packet() {
    let (mesh, n) = doubled_torus();
    let trees: Vec<Bvh> = BvhPreset::ALL.iter().map(|&p| Bvh::build(&mesh, p)).collect();
    let (lo, hi) = mesh.bounds().unwrap();
    let camera = crate::scene::camera::Camera::new(crate::scene::framing::frame_bounds(lo, hi), 64, 64).unwrap();
    let bits = |h: Option<Hit>| h.map(|h| (h.triangle, [h.t, h.b1, h.b2].map(f32::to_bits)));
    let mut hits = 0;
    for py in 0..64 {
        // A row of 16 pixels at a time: packets of rays of neighbouring pixels.
        for px0 in (0..64).step_by(PACKET) {
            let rays: Vec<(Vec3, Vec3, f32)> = (px0..px0 + PACKET as u32)
                .map(|px| {
                    let r = camera.ray((px as f32 + 0.5) / 64.0, (py as f32 + 0.5) / 64.0);
                    (r.origin, r.direction, r.t_max)
                })
                .collect();
            for (k, &(o, d, t)) in rays.iter().enumerate() {
                let want = trees[0].intersect(o, d, t);
                if let Some(h) = want {
                    assert!(
                        h.triangle < n,
                        "pixel ({}, {py}): the copy {} won",
                        px0 + k as u32,
                        h.triangle
                    );
                    hits += 1;
                }
                for (tree, preset) in trees.iter().zip(BvhPreset::ALL) {
                    assert_eq!(bits(tree.intersect(o, d, t)), bits(want), "{preset:?}");
                }
            }
            for (tree, preset) in trees.iter().zip(BvhPreset::ALL) {
                let mut got = [None; PACKET];
                tree.intersect_packet(&rays, &mut got);
                for (&(o, d, t), got) in rays.iter().zip(got) {
                    assert_eq!(bits(got), bits(trees[0].intersect(o, d, t)), "{preset:?} packet");
                }
            }
        }
    }
    assert!(hits > 500, "the torus should fill part of the frame: {hits} hits");
}

#[test]
fn scale_is_a_power_of_two() {
    let s = world_to_bvh_scale(quad(0.0, 3.7e-5, Vec3::ZERO).bounds());
    assert_eq!(s.log2().fract(), 0.0);
    assert!(s > 1.0);
}
