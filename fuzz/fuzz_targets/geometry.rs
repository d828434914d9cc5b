//! Geometry, structure-aware: arbitrary triangles (also fans and coincident copies), scaled and
//! moved, through the BVH build (each preset), the wide collapse, and both traversals — single
//! rays and packets, closest hits and shadow queries — which must agree ray for ray.
#![no_main]
use arbitrary::Arbitrary;
use glam::Vec3;
use libfuzzer_sys::fuzz_target;
use pointshade::accel::{Bvh, BvhPreset};
use pointshade::scene::mesh::TriangleMesh;

#[derive(Arbitrary, Debug)]
struct Input {
    triangles: Vec<[[f32; 3]; 3]>,
    /// A fan of this many triangles around the first vertex is added (the degenerate case).
    fan: u16,
    scale: f32,
    translate: [f32; 3],
    preset: u8,
    rays: Vec<([f32; 3], [f32; 3])>,
}

fuzz_target!(|input: Input| {
    let scale = if input.scale.is_finite() && input.scale != 0.0 {
        input.scale
    } else {
        1.0
    };
    let offset = Vec3::from(input.translate);
    if !offset.is_finite() {
        return;
    }
    let mut positions: Vec<Vec3> = Vec::new();
    for t in input.triangles.iter().take(4096) {
        positions.extend(t.iter().map(|&p| Vec3::from(p) * scale + offset));
    }
    let n = positions.len() / 3;
    let mut triangles: Vec<[u32; 3]> = (0..n as u32).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
    let fan = input.fan.min(20_000) as u32;
    if fan > 0 {
        let base = positions.len() as u32;
        positions.push(offset);
        for k in 0..=fan {
            let a = std::f32::consts::PI * k as f32 / fan as f32;
            positions.push(offset + Vec3::new(a.cos(), a.sin(), 0.0) * scale);
        }
        triangles.extend((0..fan).map(|k| [base, base + k + 1, base + k + 2]));
    }
    if triangles.is_empty() || !positions.iter().all(|p| p.is_finite()) {
        return; // the loaders refuse non-finite vertices and empty meshes
    }
    let mesh = TriangleMesh {
        normals: vec![Vec3::Z; positions.len()],
        material_of_triangle: vec![0; triangles.len()],
        positions,
        triangles,
        ..Default::default()
    };
    if std::env::var_os("POINTSHADE_FUZZ_DEBUG").is_some() {
        eprintln!(
            "{} triangles, fan {fan}, scale {scale:e}, offset {offset}, first {:?}",
            mesh.triangles.len(),
            &mesh.positions[..mesh.positions.len().min(6)]
        );
    }
    let preset = [BvhPreset::Fastest, BvhPreset::Fast, BvhPreset::Medium][input.preset as usize % 3];
    let bvh = Bvh::build(&mesh, preset);
    assert!(bvh.depth() <= 128, "depth {}", bvh.depth());
    let rays: Vec<(Vec3, Vec3, f32)> = input
        .rays
        .iter()
        .take(64)
        .filter_map(|&(o, d)| {
            let (o, d) = (Vec3::from(o), Vec3::from(d));
            let d = d.try_normalize()?;
            o.is_finite().then_some((o, d, f32::INFINITY))
        })
        .collect();
    let mut hits = vec![None; rays.len()];
    let mut occluded = vec![false; rays.len()];
    for chunk in 0..rays.len().div_ceil(8) {
        let range = chunk * 8..(chunk * 8 + 8).min(rays.len());
        bvh.intersect_packet(&rays[range.clone()], &mut hits[range.clone()]);
        bvh.any_hit_packet(&rays[range.clone()], &mut occluded[range]);
    }
    for (k, &(o, d, t_max)) in rays.iter().enumerate() {
        let single = bvh.intersect(o, d, t_max);
        assert_eq!(
            single.map(|h| (h.triangle, h.t)),
            hits[k].map(|h| (h.triangle, h.t)),
            "ray {k}"
        );
        assert_eq!(bvh.any_hit(o, d, t_max), occluded[k], "shadow ray {k}");
        assert_eq!(single.is_some(), occluded[k], "a closest hit is a hit");
    }
});
