//! A far-heavy scene for MFFR (Preißner 2020 §4.3.1: only scenes with much beyond the split gain):
//! a city of blocks from 28 m out to 400 m in every direction, a few objects near the viewer.

use glam::{Mat4, Quat, Vec3};

use super::default_scene::{hash01, palette};
use super::{cube, ground_grid, uv_sphere, DrawBatch, Instance, Scene};
use crate::view::look_at_head;

/// Streets every 12 m; blocks 5–10 m wide and 20–120 m tall, none closer than 28 m: seen from
/// the street, several blocks stand behind every far pixel.
pub fn city_scene() -> Scene {
    let meshes = vec![ground_grid(420.0, 0.25), cube(), uv_sphere(48, 24)];
    let (ground, cube_mesh, sphere) = (0, 1, 2);
    let mut blocks = Vec::new();
    let street = 12.0;
    let half = 33;
    for ix in -half..=half {
        for iz in -half..=half {
            let i = ((ix + half) * (2 * half + 1) + iz + half) as u32;
            let centre = Vec3::new(ix as f32 * street, 0.0, iz as f32 * street);
            if centre.length() < 28.0 {
                continue;
            }
            let width = 5.0 + 5.0 * hash01(i, 31);
            let height = 20.0 + 100.0 * hash01(i, 32);
            let pos = centre + Vec3::new(0.0, height * 0.5, 0.0);
            blocks.push(Instance::new(
                Mat4::from_scale_rotation_translation(
                    Vec3::new(width, height, width),
                    Quat::IDENTITY,
                    pos,
                ),
                palette(300 + i) * 0.85,
            ));
        }
    }
    // The near field: a few cubes and spheres within 2–12 m.
    for i in 0..8u32 {
        let a = (i as f32 - 3.5) * 0.3;
        let d = 2.0 + 10.0 * hash01(i, 33);
        let s = 0.3 + 0.4 * hash01(i, 34);
        let pos = Vec3::new(d * a.sin(), s, -d * a.cos());
        blocks.push(Instance::new(
            Mat4::from_scale_rotation_translation(
                Vec3::splat(2.0 * s),
                Quat::from_rotation_y(a),
                pos,
            ),
            palette(i),
        ));
    }
    let spheres = (0..6u32)
        .map(|i| {
            let a = (i as f32 - 2.5) * 0.4;
            let d = 4.0 + 8.0 * hash01(i, 35);
            let r = 0.5 + 0.5 * hash01(i, 36);
            Instance::new(
                Mat4::from_scale_rotation_translation(
                    Vec3::splat(r),
                    Quat::IDENTITY,
                    Vec3::new(d * a.sin(), r, -d * a.cos()),
                ),
                palette(50 + i),
            )
        })
        .collect();
    Scene {
        meshes,
        batches: vec![
            DrawBatch {
                mesh: ground,
                instances: vec![Instance::new(Mat4::IDENTITY, Vec3::new(0.3, 0.3, 0.32))],
            },
            DrawBatch {
                mesh: cube_mesh,
                instances: blocks,
            },
            DrawBatch {
                mesh: sphere,
                instances: spheres,
            },
        ],
        head: look_at_head(Vec3::new(0.0, 1.7, 0.0), Vec3::new(0.0, 2.5, -10.0)),
        light_dir: Vec3::new(-0.5, -1.0, -0.3).normalize(),
        materials: Vec::new(),
        lights: Vec::new(),
        reach: None,
    }
}
