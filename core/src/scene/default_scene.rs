use glam::{Mat4, Quat, Vec3};

use super::{cube, ground_grid, uv_sphere, DrawBatch, Instance, Scene};
use crate::view::look_at_head;

/// A cheap deterministic hash to vary colours and sizes without a random generator.
pub(super) fn hash01(i: u32, salt: u32) -> f32 {
    let mut x = i.wrapping_mul(0x9E37_79B9) ^ salt.wrapping_mul(0x85EB_CA6B);
    x ^= x >> 15;
    x = x.wrapping_mul(0x2C1B_3C6D);
    x ^= x >> 12;
    (x & 0xFFFF) as f32 / 65535.0
}

pub(super) fn palette(i: u32) -> Vec3 {
    Vec3::new(
        0.35 + 0.6 * hash01(i, 1),
        0.35 + 0.6 * hash01(i, 2),
        0.35 + 0.6 * hash01(i, 3),
    )
}

/// The default scene: lit cubes and high-poly spheres on a ground plane, with content from
/// arm's length to a few hundred metres so both stereo disparity (near) and its absence (far)
/// are visible.
pub fn default_scene() -> Scene {
    let meshes = vec![ground_grid(300.0, 0.25), cube(), uv_sphere(96, 48)];
    let (ground, cube_mesh, sphere) = (0, 1, 2);

    let ground_batch = DrawBatch {
        mesh: ground,
        instances: vec![Instance::new(Mat4::IDENTITY, Vec3::new(0.32, 0.38, 0.28))],
    };

    let mut cubes = Vec::new();
    // A near arc of cubes at 1.5–4 m, turned to show two or three faces each.
    for i in 0..9u32 {
        let a = (i as f32 - 4.0) * 0.22;
        let d = 1.6 + 0.3 * (i % 3) as f32;
        let size = 0.25 + 0.1 * hash01(i, 7);
        let pos = Vec3::new(d * a.sin(), 0.9 + 0.5 * hash01(i, 8), -d * a.cos());
        let rot = Quat::from_euler(glam::EulerRot::YXZ, 0.6 + i as f32, 0.5, 0.2);
        cubes.push(Instance::new(
            Mat4::from_scale_rotation_translation(Vec3::splat(size), rot, pos),
            palette(i),
        ));
    }
    // A far field of tall blocks from 40 m to 300 m.
    for i in 0..120u32 {
        let angle = -1.2 + 2.4 * hash01(i, 11);
        let dist = 40.0 + 260.0 * hash01(i, 12);
        let height = 6.0 + 30.0 * hash01(i, 13);
        let width = 4.0 + 8.0 * hash01(i, 14);
        let pos = Vec3::new(dist * angle.sin(), height * 0.5, -dist * angle.cos());
        let scale = Vec3::new(width, height, width);
        let rot = Quat::from_rotation_y(hash01(i, 15) * 1.5);
        cubes.push(Instance::new(
            Mat4::from_scale_rotation_translation(scale, rot, pos),
            palette(100 + i) * 0.8,
        ));
    }

    // High-poly spheres at mid distance, 3–20 m.
    let spheres = (0..12u32)
        .map(|i| {
            let angle = -0.9 + 1.8 * (i as f32 / 11.0);
            let dist = 3.0 + 17.0 * hash01(i, 21);
            let radius = 0.4 + 1.2 * hash01(i, 22);
            let pos = Vec3::new(dist * angle.sin(), radius, -dist * angle.cos());
            Instance::new(
                Mat4::from_scale_rotation_translation(Vec3::splat(radius), Quat::IDENTITY, pos),
                palette(200 + i),
            )
        })
        .collect();

    Scene {
        meshes,
        batches: vec![
            ground_batch,
            DrawBatch {
                mesh: cube_mesh,
                instances: cubes,
            },
            DrawBatch {
                mesh: sphere,
                instances: spheres,
            },
        ],
        head: look_at_head(Vec3::new(0.0, 1.6, 0.0), Vec3::new(0.0, 1.3, -10.0)),
        light_dir: Vec3::new(-0.4, -1.0, -0.5).normalize(),
        materials: Vec::new(),
        lights: Vec::new(),
        reach: None,
    }
}

/// A fill-bound scene: 24 walls facing the viewer, each wider than any headset's view, drawn
/// back to front so every fragment of every wall passes the depth test (24× overdraw) — the
/// workload foveation is meant for (Di Donato 2017 §2.2: "fragment bound").
pub fn fill_scene() -> Scene {
    let walls = (0..24u32)
        .map(|i| {
            let depth = 30.0 - i as f32;
            let size = depth * 8.0;
            let model = Mat4::from_scale_rotation_translation(
                Vec3::new(size, 1.0, size),
                Quat::from_rotation_x(std::f32::consts::FRAC_PI_2),
                Vec3::new(0.0, 1.6, -depth),
            );
            Instance::new(model, palette(300 + i))
        })
        .collect();
    Scene {
        meshes: vec![super::ground_quad()],
        batches: vec![DrawBatch {
            mesh: 0,
            instances: walls,
        }],
        head: look_at_head(Vec3::new(0.0, 1.6, 0.0), Vec3::new(0.0, 1.6, -10.0)),
        light_dir: Vec3::new(0.0, 0.0, -1.0),
        materials: Vec::new(),
        lights: Vec::new(),
        reach: None,
    }
}
