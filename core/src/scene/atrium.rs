//! `atrium`: an arcaded courtyard in the spirit of the Sponza atrium that foveation papers
//! measure on — a marble floor, two storeys of columns and arches, a balustraded gallery,
//! hanging fabric, bronze vases and wooden benches, stone walls; near detail (the first
//! columns, a bench at arm's length) and far detail (the end wall 25 m away), every surface
//! textured with high-frequency detail and lit by the sun, four warm lights and the sky.

use std::borrow::Cow;

use glam::{Mat4, Quat, Vec3};

use super::materials::{Material, Pattern, PointLight, Surface};
use super::{cube, cylinder, ground_grid, uv_sphere, DrawBatch, Instance, Scene};
use crate::view::look_at_head;

const MARBLE: u32 = 0;
const STONE: u32 = 1;
const PLASTER: u32 = 2;
const COLUMN: u32 = 3;
const FABRIC: u32 = 4;
const BRONZE: u32 = 5;
const WOOD: u32 = 6;

fn materials() -> Vec<Material> {
    let m = |name, pattern, base_color: Vec3, metallic, roughness, world_uv_scale| Material {
        name: Cow::Borrowed(name),
        surface: Surface::Pattern(pattern),
        base_color,
        metallic,
        roughness,
        world_uv_scale,
        alpha_cutoff: None,
    };
    vec![
        m("marble floor", Pattern::Marble, Vec3::ONE, 0.0, 1.0, 0.5),
        m("stone", Pattern::Stone, Vec3::ONE, 0.0, 1.0, 0.6),
        m(
            "plaster",
            Pattern::Plaster,
            Vec3::new(1.0, 0.95, 0.88),
            0.0,
            1.0,
            1.5,
        ),
        m(
            "column marble",
            Pattern::Marble,
            Vec3::new(1.0, 0.95, 0.85),
            0.0,
            1.0,
            1.0,
        ),
        m("fabric", Pattern::Fabric, Vec3::ONE, 0.0, 1.0, 1.5),
        m("bronze", Pattern::Bronze, Vec3::ONE, 1.0, 1.0, 2.0),
        m("wood", Pattern::Wood, Vec3::ONE, 0.0, 1.0, 1.0),
    ]
}

/// Half the courtyard's width to the column axes, and to the outer walls; half its length.
const COLONNADE_X: f32 = 4.0;
const WALL_X: f32 = 7.0;
const HALF_LENGTH: f32 = 14.0;
/// Columns along each side, bay width.
const BAYS: u32 = 11;
const BAY: f32 = 2.5;

/// Pieces the long walls, galleries and rails are built of: no piece crosses the eye plane
/// where either eye could see it (a multiview driver quirk mis-draws clipped primitives; see
/// `DriverQuirks::multiview_clipping_drops_views`), as on a real building of separate stones.
const PIECES: u32 = 12;

/// Where the viewer stands.
const HEAD: Vec3 = Vec3::new(0.0, 1.6, 10.5);

/// The atrium, lit. Looking down its length from one end, eye height 1.6 m.
/// The atrium's meshes, by index.
const BOXES: usize = 0;
const COLUMN_MESH: usize = 1;
const BALUSTER: usize = 2;
const SPHERE: usize = 3;
const FLOOR: usize = 4;
const WHITE: Vec3 = Vec3::ONE;
const NONE: Quat = Quat::IDENTITY;

/// The atrium's batches as they are filled, one per mesh, in the order of the scene's parts.
struct Atrium {
    batches: Vec<DrawBatch>,
}

impl Atrium {
    fn put(
        &mut self,
        mesh: usize,
        material: u32,
        scale: Vec3,
        rotation: Quat,
        at: Vec3,
        tint: Vec3,
    ) {
        self.batches[mesh].instances.push(
            Instance::new(
                Mat4::from_scale_rotation_translation(scale, rotation, at),
                tint,
            )
            .with_material(material),
        );
    }
}

/// The atrium: an arcaded courtyard, lit and textured, looked down from one end at eye height.
pub fn atrium_scene() -> Scene {
    let meshes = vec![
        cube(),
        cylinder(24),
        cylinder(12),
        uv_sphere(32, 16),
        // Fine under the viewer, coarse far away (the same quirk).
        ground_grid(26.0, 0.25),
    ];
    let mut a = Atrium {
        batches: (0..meshes.len())
            .map(|mesh| DrawBatch {
                mesh,
                instances: Vec::new(),
            })
            .collect(),
    };
    walls_and_galleries(&mut a);
    floor_ends_and_door(&mut a);
    arcades(&mut a);
    courtyard(&mut a);
    let batches = a.batches;
    Scene {
        meshes,
        batches,
        head: look_at_head(HEAD, Vec3::new(0.0, 2.6, -10.0)),
        light_dir: Vec3::new(-0.35, -1.0, -0.45).normalize(),
        materials: materials(),
        lights: [(-3.3, -7.0), (3.3, -7.0), (-3.3, 2.5), (3.3, 2.5)]
            .map(|(x, z)| PointLight {
                position: Vec3::new(x, 2.9, z),
                color: Vec3::new(1.0, 0.72, 0.45) * 8.0,
                range: 9.0,
            })
            .to_vec(),
        reach: None,
    }
}

fn walls_and_galleries(a: &mut Atrium) {
    // Outer walls (stone below, plaster above), the galleries over the aisles (wood beneath, a
    // stone edge), their rails and architraves: each the courtyard's length, in pieces.
    let piece = 2.0 * HALF_LENGTH / PIECES as f32;
    for side in [-1.0f32, 1.0] {
        let x = side * COLONNADE_X;
        let runs = [
            (STONE, (0.4, 5.0), side * WALL_X, 2.5),
            (PLASTER, (0.4, 4.0), side * WALL_X, 7.0),
            (
                WOOD,
                (WALL_X - COLONNADE_X + 0.4, 0.3),
                side * (WALL_X + COLONNADE_X) * 0.5,
                4.75,
            ),
            (STONE, (0.6, 0.5), x, 4.7),
            (STONE, (0.3, 0.12), x, 5.8),
            (STONE, (0.7, 0.5), x, 8.25),
        ];
        for (material, (w, h), x, y) in runs {
            for k in 0..PIECES {
                let z = -HALF_LENGTH + piece * (k as f32 + 0.5);
                a.put(
                    BOXES,
                    material,
                    Vec3::new(w, h, piece),
                    NONE,
                    Vec3::new(x, y, z),
                    WHITE,
                );
            }
        }
    }
}

fn floor_ends_and_door(a: &mut Atrium) {
    // The FLOOR, centred under the viewer; the end walls.
    a.put(
        FLOOR,
        MARBLE,
        Vec3::ONE,
        NONE,
        Vec3::new(HEAD.x, 0.0, HEAD.z),
        WHITE,
    );
    for end in [-1.0f32, 1.0] {
        a.put(
            BOXES,
            STONE,
            Vec3::new(2.0 * WALL_X, 9.0, 0.4),
            NONE,
            Vec3::new(0.0, 4.5, end * HALF_LENGTH),
            WHITE,
        );
    }
    // A great door in the far wall, and its bronze boss.
    a.put(
        BOXES,
        WOOD,
        Vec3::new(2.4, 3.6, 0.2),
        NONE,
        Vec3::new(0.0, 1.8, -HALF_LENGTH + 0.25),
        WHITE,
    );
    a.put(
        SPHERE,
        BRONZE,
        Vec3::splat(0.25),
        NONE,
        Vec3::new(0.0, 1.6, -HALF_LENGTH + 0.4),
        WHITE,
    );
}

/// Both colonnades: two storeys of columns, round arches between them, balusters along the
/// gallery and fabric hanging in every other bay.
fn arcades(a: &mut Atrium) {
    for side in [-1.0f32, 1.0] {
        let x = side * COLONNADE_X;
        for i in 0..BAYS {
            let z = -HALF_LENGTH + 1.75 + BAY * i as f32;
            // Ground storey: base, shaft, capital.
            a.put(
                BOXES,
                STONE,
                Vec3::new(0.8, 0.3, 0.8),
                NONE,
                Vec3::new(x, 0.15, z),
                WHITE,
            );
            a.put(
                COLUMN_MESH,
                COLUMN,
                Vec3::new(0.55, 2.9, 0.55),
                NONE,
                Vec3::new(x, 1.75, z),
                WHITE,
            );
            a.put(
                BOXES,
                STONE,
                Vec3::new(0.8, 0.3, 0.8),
                NONE,
                Vec3::new(x, 3.35, z),
                WHITE,
            );
            // Upper storey: a slimmer shaft on the gallery.
            a.put(
                COLUMN_MESH,
                COLUMN,
                Vec3::new(0.4, 2.6, 0.4),
                NONE,
                Vec3::new(x, 6.5, z),
                WHITE,
            );
            a.put(
                BOXES,
                STONE,
                Vec3::new(0.6, 0.25, 0.6),
                NONE,
                Vec3::new(x, 7.9, z),
                WHITE,
            );
            if i + 1 == BAYS {
                continue;
            }
            // A round arch to the next column: nine voussoirs on a semicircle.
            let centre = Vec3::new(x, 3.5, z + BAY * 0.5);
            let radius = BAY * 0.5 - 0.35;
            for k in 0..9 {
                let angle = std::f32::consts::PI * (k as f32 + 0.5) / 9.0;
                let at = centre + Vec3::new(0.0, radius * angle.sin(), -radius * angle.cos());
                let rotation = Quat::from_rotation_x(angle - std::f32::consts::FRAC_PI_2);
                a.put(BOXES, STONE, Vec3::new(0.5, 0.3, 0.36), rotation, at, WHITE);
            }
            // Balusters along the gallery's edge, and hanging fabric in every other bay.
            for b in 0..8 {
                let bz = z + 0.45 + 0.2 * b as f32;
                a.put(
                    BALUSTER,
                    COLUMN,
                    Vec3::new(0.1, 0.8, 0.1),
                    NONE,
                    Vec3::new(x, 5.35, bz),
                    WHITE,
                );
            }
            if i % 2 == 0 {
                let tint = [
                    Vec3::new(0.8, 0.15, 0.12),
                    Vec3::new(0.15, 0.45, 0.2),
                    Vec3::new(0.15, 0.2, 0.6),
                ][(i as usize / 2) % 3];
                a.put(
                    BOXES,
                    FABRIC,
                    Vec3::new(0.04, 2.2, 1.8),
                    NONE,
                    Vec3::new(x - side * 0.3, 6.6, z + BAY * 0.5),
                    tint,
                );
            }
        }
    }
}

fn courtyard(a: &mut Atrium) {
    // In the courtyard: a fountain, vases on pedestals and benches, the nearest at arm's length.
    a.put(
        COLUMN_MESH,
        MARBLE,
        Vec3::new(3.0, 0.6, 3.0),
        NONE,
        Vec3::new(0.0, 0.3, -2.0),
        WHITE,
    );
    a.put(
        COLUMN_MESH,
        COLUMN,
        Vec3::new(0.4, 1.6, 0.4),
        NONE,
        Vec3::new(0.0, 1.1, -2.0),
        WHITE,
    );
    a.put(
        SPHERE,
        BRONZE,
        Vec3::splat(0.45),
        NONE,
        Vec3::new(0.0, 2.2, -2.0),
        WHITE,
    );
    for (k, z) in [-10.0f32, -6.0, 2.0, 6.0].into_iter().enumerate() {
        for side in [-1.0f32, 1.0] {
            let at = Vec3::new(side * 2.3, 0.0, z);
            a.put(
                BOXES,
                STONE,
                Vec3::new(0.6, 0.9, 0.6),
                NONE,
                at + Vec3::Y * 0.45,
                WHITE,
            );
            a.put(
                SPHERE,
                BRONZE,
                Vec3::new(0.35, 0.45, 0.35),
                NONE,
                at + Vec3::Y * 1.3,
                WHITE,
            );
            let bench = Quat::from_rotation_y(0.1 * (k as f32 - 1.5));
            a.put(
                BOXES,
                WOOD,
                Vec3::new(0.5, 0.1, 1.8),
                bench,
                Vec3::new(side * 1.4, 0.45, z + 1.6),
                WHITE,
            );
        }
    }
    a.put(
        BOXES,
        WOOD,
        Vec3::new(0.5, 0.1, 1.4),
        Quat::from_rotation_y(0.4),
        Vec3::new(0.6, 0.7, 9.0),
        WHITE,
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_atrium_is_lit_and_every_instance_has_a_material() {
        let scene = atrium_scene();
        assert_eq!(scene.shading(), super::super::Shading::Lit);
        assert!(scene.lights.len() <= super::super::materials::MAX_POINT_LIGHTS);
        for b in &scene.batches {
            for i in &b.instances {
                assert!((i.material as usize) < scene.materials.len());
            }
        }
        assert!(
            scene.triangle_count() > 20_000,
            "{}",
            scene.triangle_count()
        );
    }
}
