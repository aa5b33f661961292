//! The hard cases of culling, named one by one: half angles near 0° and 90°, spheres at a
//! cone's apex and behind its plane, tiny and huge radii, and the stereo strategies at their
//! edges — each checked against the `f64` oracles (the property tests are in `tests.rs`).

use std::f32::consts::FRAC_PI_2;

use glam::{Mat4, Quat, Vec3};

use super::oracle;
use super::{
    Cone, CullHierarchy, CullResult, DualCone, Frustum, HierarchyParams, PerEye, Relation,
    RoundRobin, Sphere, StereoCull, StereoFrusta, Superfrustum,
};
use crate::view::{Eye, EyeParams, FovTangents, LensRegion};

fn eye_at_origin(fov: FovTangents, near: f32, far: f32) -> Frustum {
    Frustum::from_eye(Mat4::IDENTITY, fov, near, far)
}

#[test]
fn half_angle_near_0_degrees() {
    let cone = Cone::new(Vec3::ZERO, Vec3::NEG_Z, 1e-5);
    // On the axis far away, and just off it by its radius.
    assert!(cone.intersects_sphere(&Sphere::new(Vec3::new(0.0, 0.0, -1e4), 1e-6)));
    let off = Sphere::new(Vec3::new(0.5, 0.0, -100.0), 0.5 + 1e-3);
    assert!(oracle::sphere_cone(&cone, &off) && cone.intersects_sphere(&off));
    assert!(!cone.intersects_sphere(&Sphere::new(Vec3::new(2.0, 0.0, -100.0), 0.5)));
}

#[test]
fn half_angle_near_90_degrees() {
    let cone = Cone::new(Vec3::ZERO, Vec3::NEG_Z, FRAC_PI_2 - 1e-5);
    // Almost a half-space: points just in front of the plane are in.
    assert!(cone.contains_point_tan(Vec3::new(1e3, 0.0, -0.1)));
    let grazing = Sphere::new(Vec3::new(1e3, 0.0, 0.5), 0.51);
    assert!(oracle::sphere_cone(&cone, &grazing));
    assert!(cone.intersects_sphere(&grazing));
}

/// Hale's Listing 3.2 verbatim: it rejects spheres centred behind `z = −r·cos θ` without
/// looking at the apex. Our test must not.
fn hale_listing_3_2(center_in_cone_space: Vec3, radius: f32, half: f32) -> bool {
    let (s, c, t) = (half.sin(), half.cos(), half.tan());
    if center_in_cone_space.z > -radius * c {
        let cone_radius = t * (center_in_cone_space.z + radius / s);
        return center_in_cone_space.truncate().length_squared() <= cone_radius * cone_radius;
    }
    false
}

#[test]
fn sphere_at_the_apex() {
    let half = 0.3f32;
    let cone = Cone::new(Vec3::ZERO, Vec3::Z, half);
    // Centred just behind the apex, reaching over it.
    let s = Sphere::new(Vec3::new(0.0, 0.0, -0.99), 1.0);
    assert!(oracle::sphere_cone(&cone, &s));
    assert!(
        !hale_listing_3_2(s.center, s.radius, half),
        "Hale's listing misses it"
    );
    assert!(cone.intersects_sphere(&s), "ours does not");
    assert!(cone.intersects_sphere(&Sphere::new(Vec3::ZERO, 1e-6)));
}

#[test]
fn sphere_straddling_and_behind_the_cone_plane() {
    let cone = Cone::new(Vec3::ZERO, Vec3::Z, 0.8);
    let straddling = Sphere::new(Vec3::new(1.0, 0.0, -0.2), 0.6);
    assert_eq!(
        cone.intersects_sphere(&straddling),
        oracle::sphere_cone(&cone, &straddling)
    );
    let behind = Sphere::new(Vec3::new(0.0, 0.0, -2.0), 1.0);
    assert!(!oracle::sphere_cone(&cone, &behind) && !cone.intersects_sphere(&behind));
    let behind_touching = Sphere::new(Vec3::new(0.3, 0.0, -1.0), 1.05);
    assert!(
        oracle::sphere_cone(&cone, &behind_touching) && cone.intersects_sphere(&behind_touching)
    );
}

#[test]
fn tiny_and_huge_radii() {
    let f = eye_at_origin(FovTangents::symmetric_deg(90.0, 90.0), 0.1, 1e4);
    for r in [1e-6f32, 1e-3, 1.0, 1e2, 1e4] {
        // Just outside the right plane by less than r.
        let x = 10.0 + r * 0.5_f32.sqrt() * 0.9;
        let s = Sphere::new(Vec3::new(x, 0.0, -10.0), r);
        assert!(oracle::sphere_frustum(&f, &s), "r {r}");
        assert!(f.intersects_sphere(&s), "r {r}");
    }
    // A huge sphere enclosing the whole frustum.
    assert_eq!(
        f.sphere(&Sphere::new(Vec3::ZERO, 1e5)),
        Relation::Intersecting
    );
}

#[test]
fn positions_up_to_1e6() {
    let eye = Mat4::from_translation(Vec3::new(1e6, -1e6, 1e6));
    let f = Frustum::from_eye(eye, FovTangents::symmetric_deg(100.0, 100.0), 0.05, 500.0);
    let touching = Sphere::new(Vec3::new(1e6, -1e6 + 0.5, 1e6 - 100.0), 1e-6);
    assert!(f.intersects_sphere(&touching));
    let cone = Cone::new(Vec3::splat(1e6), Vec3::X, 0.5);
    let s = Sphere::new(
        Vec3::new(1e6 + 100.0, 1e6 + 100.0 * 0.5f32.tan() + 1e-3, 1e6),
        2e-3,
    );
    assert!(oracle::sphere_cone(&cone, &s) && cone.intersects_sphere(&s));
}

#[test]
fn ipd_0_superfrustum_equals_the_eye_frustum() {
    let fov = FovTangents::symmetric_deg(100.0, 90.0);
    let eyes = EyeParams {
        left_fov: fov,
        right_fov: fov,
        ipd_m: 0.0,
        cant_rad: 0.0,
    };
    let sf = Superfrustum::new(&eyes, Mat4::IDENTITY, 0.05, 300.0);
    let eye = StereoFrusta::new(&eyes, Mat4::IDENTITY, 0.05, 300.0).eyes[0];
    assert_eq!(sf.recession, 0.0);
    for (a, b) in sf.fov.as_array().iter().zip(fov.as_array()) {
        assert!(a >= &b && (a - b) <= 2e-5 * b, "{:?} vs {fov:?}", sf.fov);
    }
    for (a, b) in sf.frustum.world_corners().iter().zip(eye.world_corners()) {
        assert!((*a - b).length() < 1e-3 * b.length().max(1.0), "{a} vs {b}");
    }
}

#[test]
fn parallel_superfrustum_recession_is_oddous() {
    // Oddou: recession = ipd / (tan θ₀ + tan θ₁) with the outer half-angles.
    let fov = FovTangents {
        left: 1.4,
        right: 1.2,
        up: 1.4,
        down: 1.4,
    };
    let eyes = EyeParams {
        left_fov: fov,
        right_fov: fov.mirrored(),
        ipd_m: 0.064,
        cant_rad: 0.0,
    };
    let sf = Superfrustum::new(&eyes, Mat4::IDENTITY, 0.05, 100.0);
    assert!(
        (sf.recession - 0.064 / (1.4 + 1.4)).abs() < 1e-6,
        "{}",
        sf.recession
    );
    assert!((sf.fov.left - 1.4).abs() < 1e-4 && (sf.fov.right - 1.4).abs() < 1e-4);
}

#[test]
fn canted_eyes_plus_minus_5_and_10_degrees() {
    let fov = FovTangents::from_angles_deg(52.0, 45.0, 48.0, 50.0);
    for cant in [-10.0f32, -5.0, 5.0, 10.0] {
        let eyes = EyeParams {
            left_fov: fov,
            right_fov: fov.mirrored(),
            ipd_m: 0.064,
            cant_rad: cant.to_radians(),
        };
        let head =
            Mat4::from_rotation_translation(Quat::from_rotation_y(0.3), Vec3::new(5.0, 1.6, -3.0));
        let sf = Superfrustum::new(&eyes, head, 0.05, 320.0);
        for f in StereoFrusta::new(&eyes, head, 0.05, 320.0).eyes {
            assert!(
                f.world_corners()
                    .iter()
                    .all(|&c| sf.frustum.contains_point(c)),
                "cant {cant}"
            );
        }
    }
}

#[test]
fn rift_cv1_asymmetric_fov() {
    let hmd = crate::view::HmdProfile::by_name("rift-cv1").unwrap();
    let eyes = hmd.eyes(0.064);
    let regions = Eye::BOTH
        .map(|e| LensRegion::with_hidden_fraction(eyes.fov(e), hmd.hidden_area_fraction.unwrap()));
    let head = Mat4::IDENTITY;
    let circular = DualCone::new(&eyes, head, &regions, false);
    let elliptical = DualCone::new(&eyes, head, &regions, true);
    // Hale: a circular cone around an asymmetric eye is looser than the frustum; the elliptical
    // cone is tighter than the circular one (smaller solid angle ⇒ smaller cross-section area).
    let c = circular.cones[0];
    let e = elliptical.elliptical_cones[0];
    assert!(
        e.tan_x * e.tan_y < c.tan * c.tan,
        "elliptical {} x {} vs circular {}",
        e.tan_x,
        e.tan_y,
        c.tan
    );
    let sf = Superfrustum::new(&eyes, head, 0.05, 100.0);
    assert!(sf.fov.left >= eyes.left_fov.left && sf.fov.right >= eyes.right_fov.right);
}

#[test]
fn near_plane_at_1e_minus_4() {
    let f = eye_at_origin(FovTangents::symmetric_deg(90.0, 90.0), 1e-4, 100.0);
    let at_near = Sphere::new(Vec3::new(0.0, 0.0, -5e-5), 5.1e-5);
    assert!(oracle::sphere_frustum(&f, &at_near) && f.intersects_sphere(&at_near));
    let behind = Sphere::new(Vec3::new(0.0, 0.0, 1e-3), 1e-4);
    assert!(!f.intersects_sphere(&behind));
}

#[test]
fn point_tests_agree() {
    let cone = Cone::new(Vec3::new(1.0, 2.0, 3.0), Vec3::new(0.3, -0.2, -1.0), 0.6);
    for i in 0..2000 {
        let p = Vec3::new(
            (i % 13) as f32 - 6.0,
            (i % 7) as f32 - 3.0,
            -((i % 29) as f32) + 3.0,
        );
        let exact = oracle::cone_distance(&cone, p) == 0.0;
        if (oracle::cone_distance(&cone, p)) > 1e-3 || exact {
            assert_eq!(cone.contains_point_tan(p), exact, "{p}");
            assert_eq!(cone.contains_point_cos(p), exact, "{p}");
        }
    }
}

/// Round robin culls with one eye per frame: objects only the other eye sees are missed, on
/// alternate eyes — expected, and visible in the numbers.
#[test]
fn round_robin_misses_what_only_the_other_eye_sees() {
    let fov = FovTangents::symmetric_deg(90.0, 90.0);
    let eyes = EyeParams {
        left_fov: fov,
        right_fov: fov,
        ipd_m: 0.064,
        cant_rad: 0.0,
    };
    let frusta = StereoFrusta::new(&eyes, Mat4::IDENTITY, 0.05, 100.0);
    // Just beyond the left eye's right edge, inside the right eye's view.
    let s = Sphere::new(Vec3::new(1.0 - 0.032 + 0.04, 0.0, -1.0), 0.01);
    assert!(!frusta.eyes[0].intersects_sphere(&s) && frusta.eyes[1].intersects_sphere(&s));
    assert!(!RoundRobin::new(&frusta, 0).sphere(&s));
    assert!(RoundRobin::new(&frusta, 1).sphere(&s));
    assert!(PerEye { frusta }.sphere(&s));
}

#[test]
fn hierarchy_has_no_false_negatives_against_the_exact_reference() {
    // A random field of spheres around a head.
    let mut seed = 7u32;
    let mut rand = || {
        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (seed >> 8) as f32 / (1u32 << 24) as f32
    };
    let spheres: Vec<Sphere> = (0..20_000)
        .map(|_| {
            Sphere::new(
                Vec3::new(
                    rand() * 400.0 - 200.0,
                    rand() * 60.0,
                    rand() * 400.0 - 200.0,
                ),
                0.2 + rand() * 3.0,
            )
        })
        .collect();
    let hierarchy = CullHierarchy::build(&spheres, HierarchyParams::default());
    assert_eq!(hierarchy.len(), spheres.len());
    let mut ids = hierarchy.ids.clone();
    ids.sort_unstable();
    assert!(
        ids.iter().enumerate().all(|(i, &id)| i as u32 == id),
        "every object exactly once"
    );

    let eyes = crate::view::HmdProfile::by_name("index")
        .unwrap()
        .eyes(0.064);
    let head = crate::view::look_at_head(Vec3::new(3.0, 20.0, 5.0), Vec3::new(40.0, 15.0, -60.0));
    let eye_centre = head.transform_point3(Vec3::ZERO);
    let distance = 150.0;
    let frusta = StereoFrusta::new(&eyes, head, 0.05, distance);
    let exact: Vec<bool> = (0..hierarchy.len())
        .map(|i| {
            let s = hierarchy.spheres.get(i);
            (s.center - eye_centre).length() <= distance + s.radius
                && frusta.eyes.iter().any(|f| oracle::sphere_frustum(f, &s))
        })
        .collect();
    let culled = |result: CullResult| {
        let mut accepted = vec![false; hierarchy.len()];
        for i in result.visible.indices() {
            assert!(!accepted[i as usize], "object {i} accepted twice");
            accepted[i as usize] = true;
        }
        accepted
    };
    let per_eye = culled(hierarchy.cull(&PerEye { frusta }, eye_centre, distance));
    let superfrustum = culled(hierarchy.cull(
        &Superfrustum::new(&eyes, head, 0.05, distance),
        eye_centre,
        distance,
    ));
    let visible = exact.iter().filter(|&&v| v).count();
    assert!(visible > 500, "the view sees a fair share ({visible})");
    for i in 0..hierarchy.len() {
        if exact[i] {
            assert!(
                per_eye[i] && superfrustum[i],
                "object {i} visible but culled"
            );
        }
    }
}

#[test]
fn view_transform_variant_agrees_with_the_direct_test() {
    let cone = Cone::new(Vec3::new(1.0, -2.0, 0.5), Vec3::new(0.3, 0.4, -1.0), 0.6);
    let view = cone.view();
    for i in 0..4000 {
        let f = i as f32;
        let s = Sphere::new(
            Vec3::new(
                (f * 0.37).sin() * 9.0,
                (f * 0.11).cos() * 7.0,
                -(f * 0.013) % 12.0,
            ),
            0.05 + (f * 0.7).sin().abs(),
        );
        if oracle::sphere_cone(&cone, &s) {
            assert!(
                view.intersects_sphere(&s) && cone.intersects_sphere(&s),
                "{s:?}"
            );
        }
        let p = s.center;
        if oracle::cone_distance(&cone, p) > 1e-3 || oracle::cone_distance(&cone, p) == 0.0 {
            assert_eq!(
                view.contains_point(p),
                oracle::cone_distance(&cone, p) == 0.0,
                "{p}"
            );
        }
    }
}
