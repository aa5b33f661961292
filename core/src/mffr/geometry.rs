use glam::{Mat4, Vec3, Vec4};

use super::{MffrConfig, MffrVariant, SplitDistance, FAR_DENSITY_RANGE};
use crate::view::{Eye, EyeParams, FovTangents};
use crate::vocab::{ConfigError, Resolution};

/// The far view's slot in the `Views` uniform block (after the up to six eye views).
pub const FAR_VIEW_INDEX: u32 = crate::vocab::FRAME_VIEWS;

/// The split distance at which the two eyes see a point `threshold_px` apart:
/// z = IPD · focal_px / threshold.
pub fn split_for_disparity(ipd_m: f32, focal_px: f32, threshold_px: f32) -> f32 {
    ipd_m * focal_px / threshold_px
}

/// MFFR as resolved for one frame plan: where the split is and what the far pass renders.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MffrGeometry {
    /// The configuration.
    pub config: MffrConfig,
    /// Eye-space depth where each eye's near field ends.
    pub split_m: f32,
    /// Binocular disparity at the split, in eye pixels (each eye is off by half of it with the
    /// centre variant).
    pub disparity_at_split_px: f32,
    /// The far view's field of view: oriented as the head, covering both eyes' far frusta from
    /// every origin the variant renders from.
    pub far_fov: FovTangents,
    /// The far pass's near plane (≤ the split: canted eyes' split planes tilt towards it).
    pub far_near: f32,
    /// The far pass's far plane.
    pub far: f32,
    /// The far image's size at the eyes' pixel density times the config's `far_density`.
    pub resolution: Resolution,
}

impl MffrGeometry {
    /// Resolves `config` for these eyes; `None` when nothing can lie beyond the split (it is at
    /// or past the far plane).
    pub fn resolve(
        config: MffrConfig,
        eyes: &EyeParams,
        eye: Resolution,
        near: f32,
        far: f32,
    ) -> Result<Option<Self>, ConfigError> {
        if !FAR_DENSITY_RANGE.contains(&config.far_density) {
            return Err(ConfigError::new(
                "mffr far_density",
                config.far_density,
                format!(
                    "a fraction of the eyes' pixel density in {}..={}",
                    FAR_DENSITY_RANGE.start(),
                    FAR_DENSITY_RANGE.end()
                ),
            ));
        }
        let fov = eyes.left_fov;
        let focal_px = eye.width as f32 / (fov.left + fov.right);
        let split_m = match config.split {
            SplitDistance::DisparityPx(px) => {
                if !px.is_finite() || px <= 0.0 {
                    return Err(ConfigError::new(
                        "mffr split",
                        config.split,
                        "a finite disparity > 0 px",
                    ));
                }
                split_for_disparity(eyes.ipd_m, focal_px, px)
            }
            SplitDistance::Metres(m) => m,
        };
        if !split_m.is_finite() || split_m <= near {
            return Err(ConfigError::new(
                "mffr split",
                config.split,
                format!(
                    "beyond the near plane ({near} m); it gives {split_m} m with IPD {} m and {focal_px:.0} px focal length",
                    eyes.ipd_m
                ),
            ));
        }
        if split_m >= far {
            return Ok(None);
        }
        let origins: Vec<Vec3> = match config.variant {
            MffrVariant::AlternateEye => Eye::BOTH
                .iter()
                .map(|&e| eyes.head_from_eye(e).transform_point3(Vec3::ZERO))
                .collect(),
            _ => vec![Vec3::ZERO],
        };
        let (far_fov, far_near) = covering_view(eyes, split_m, far, &origins)
            .map_err(|why| ConfigError::new("mffr split", config.split, why))?;
        // The far image at the eyes' pixel density (pixels per unit tangent), scaled.
        let density_x = focal_px * config.far_density;
        let density_y = config.far_density * eye.height as f32 / (fov.up + fov.down);
        let resolution = Resolution {
            width: ((far_fov.left + far_fov.right) * density_x).ceil() as u32,
            height: ((far_fov.up + far_fov.down) * density_y).ceil() as u32,
        };
        Ok(Some(MffrGeometry {
            config,
            split_m,
            disparity_at_split_px: eyes.ipd_m * focal_px / split_m,
            far_fov,
            far_near,
            far,
            resolution,
        }))
    }

    /// The far view's pose in head space for frame number `frame`.
    pub fn head_from_far(&self, eyes: &EyeParams, frame: u64) -> Mat4 {
        far_view_from_head(self.config.variant, eyes, frame).inverse()
    }
}

/// The far view matrix relative to the head (far ← head): the head's orientation, from the
/// head centre or, alternating by frame, from one eye.
pub fn far_view_from_head(variant: MffrVariant, eyes: &EyeParams, frame: u64) -> Mat4 {
    let origin = match variant {
        MffrVariant::AlternateEye => {
            let eye = Eye::BOTH[(frame % 2) as usize];
            eyes.head_from_eye(eye).transform_point3(Vec3::ZERO)
        }
        _ => Vec3::ZERO,
    };
    Mat4::from_translation(-origin)
}

/// The head-oriented field of view that contains both eyes' frusta between `split` and `far`
/// as seen from each of `origins` (head space), and the nearest head-space depth of the split
/// planes. The frustum slab is convex and projects to a convex region, so its eight corners
/// bound it.
fn covering_view(
    eyes: &EyeParams,
    split: f32,
    far: f32,
    origins: &[Vec3],
) -> Result<(FovTangents, f32), String> {
    let far = if far.is_finite() { far } else { split * 1e6 };
    let mut t = [f32::NEG_INFINITY; 4];
    let mut near = f32::INFINITY;
    for eye in Eye::BOTH {
        let head_from_eye = eyes.head_from_eye(eye);
        let f = eyes.fov(eye);
        for s in [split, far] {
            for (x, y) in [
                (-f.left, -f.down),
                (f.right, -f.down),
                (f.right, f.up),
                (-f.left, f.up),
            ] {
                let p = head_from_eye.transform_point3(Vec3::new(x * s, y * s, -s));
                if s == split {
                    near = near.min(-p.z);
                }
                for o in origins {
                    let rel = p - *o;
                    let depth = -rel.z;
                    if depth <= 1e-3 * s {
                        return Err(format!(
                            "a split where the {eye:?} eye's frustum still reaches behind the head plane (cant {:.1}°): no single far projection covers it",
                            eyes.cant_rad.to_degrees()
                        ));
                    }
                    let (tx, ty) = (rel.x / depth, rel.y / depth);
                    t = [t[0].max(-tx), t[1].max(tx), t[2].max(ty), t[3].max(-ty)];
                }
            }
        }
    }
    // A hair of overlap at the split: both fields draw what lies on it, so no crack opens.
    Ok((
        FovTangents {
            left: t[0],
            right: t[1],
            up: t[2],
            down: t[3],
        },
        near * (1.0 - 1e-3),
    ))
}

/// How one view finds its pixels in the far image: the far clip position of the point at
/// view depth `s` on the ray through view NDC `(x, y)` is `origin + s · direction · (x, y, 1, 0)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FarReprojection {
    /// The matrix that turns a view's NDC ray into the far image's clip space.
    pub direction: Mat4,
    /// The far clip position of the view's origin.
    pub origin: Vec4,
}

impl FarReprojection {
    /// For a view at `world_from_view` with field of view `fov`, into the far view
    /// `far_view_proj` (projection × view).
    pub fn new(world_from_view: Mat4, fov: FovTangents, far_view_proj: Mat4) -> Self {
        // View-space ray through NDC (x, y) at depth 1: x·(l+r)/2 + (r−l)/2, −y·(u+d)/2 + (u−d)/2, −1.
        let ray = Mat4::from_cols(
            Vec4::new((fov.left + fov.right) / 2.0, 0.0, 0.0, 0.0),
            Vec4::new(0.0, -(fov.up + fov.down) / 2.0, 0.0, 0.0),
            Vec4::new(
                (fov.right - fov.left) / 2.0,
                (fov.up - fov.down) / 2.0,
                -1.0,
                0.0,
            ),
            Vec4::ZERO,
        );
        let far_from_view = far_view_proj * world_from_view;
        FarReprojection {
            direction: far_from_view * ray,
            origin: far_from_view * Vec4::W,
        }
    }

    /// Where the point at view depth `s` (∞ for rotation only) on the ray through `ndc` lands
    /// in the far image's NDC.
    pub fn far_ndc(&self, ndc: glam::Vec2, s: f32) -> glam::Vec2 {
        let dir = self.direction * Vec4::new(ndc.x, ndc.y, 1.0, 0.0);
        let clip = if s.is_finite() {
            self.origin + s * dir
        } else {
            dir
        };
        glam::Vec2::new(clip.x / clip.w, clip.y / clip.w)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::view::{reverse_z_projection, HmdProfile};

    fn eyes(cant_deg: f32, fov: FovTangents) -> EyeParams {
        EyeParams {
            left_fov: fov,
            right_fov: fov.mirrored(),
            ipd_m: 0.064,
            cant_rad: cant_deg.to_radians(),
        }
    }

    #[test]
    fn split_distance_is_ipd_times_focal_over_threshold() {
        // 64 mm, 500 px focal length, 1 px: 32 m; 2 px halves it.
        assert!((split_for_disparity(0.064, 500.0, 1.0) - 32.0).abs() < 1e-4);
        assert!((split_for_disparity(0.064, 500.0, 2.0) - 16.0).abs() < 1e-4);
        let index = HmdProfile::by_name("index").unwrap();
        let e = index.eyes(0.064);
        let g = MffrGeometry::resolve(
            MffrConfig::default(),
            &e,
            Resolution::square(1024),
            0.05,
            500.0,
        )
        .unwrap()
        .unwrap();
        let focal = 1024.0 / (e.left_fov.left + e.left_fov.right);
        assert!((g.split_m - 0.064 * focal).abs() < 1e-3, "{}", g.split_m);
        assert!((g.disparity_at_split_px - 1.0).abs() < 1e-5);
    }

    #[test]
    fn bad_splits_are_errors_naming_the_field_and_a_split_past_far_plans_nothing() {
        let e = eyes(0.0, FovTangents::symmetric_deg(90.0, 90.0));
        let res = Resolution::square(256);
        for split in [
            SplitDistance::DisparityPx(0.0),
            SplitDistance::DisparityPx(f32::NAN),
            SplitDistance::Metres(0.01),
            SplitDistance::Metres(f32::INFINITY),
        ] {
            let c = MffrConfig {
                split,
                ..Default::default()
            };
            let err = MffrGeometry::resolve(c, &e, res, 0.05, 500.0).unwrap_err();
            assert_eq!(err.field, "mffr split", "{err}");
        }
        let c = MffrConfig {
            split: SplitDistance::Metres(600.0),
            ..Default::default()
        };
        assert_eq!(MffrGeometry::resolve(c, &e, res, 0.05, 500.0), Ok(None));
    }

    /// f64 oracle: the far view contains every eye's far frustum, sampled densely between the
    /// split and the far plane, for parallel, canted (±10°) and asymmetric eyes and for both
    /// the centre and the alternating-eye origins.
    #[test]
    fn far_projection_contains_both_eyes_far_frusta() {
        let fovs = [
            FovTangents::symmetric_deg(90.0, 90.0),
            HmdProfile::by_name("rift-cv1").unwrap().left_fov,
            HmdProfile::by_name("index").unwrap().left_fov,
        ];
        for fov in fovs {
            for cant in [-10.0, 0.0, 10.0] {
                for variant in [MffrVariant::Centre, MffrVariant::AlternateEye] {
                    let e = eyes(cant, fov);
                    let config = MffrConfig {
                        split: SplitDistance::Metres(20.0),
                        variant,
                        ..Default::default()
                    };
                    let g = MffrGeometry::resolve(config, &e, Resolution::square(512), 0.05, 400.0)
                        .unwrap()
                        .unwrap();
                    for frame in 0..2 {
                        let far_from_head = far_view_from_head(variant, &e, frame);
                        check_contains(&e, &g, far_from_head, cant);
                    }
                }
            }
        }
    }

    fn check_contains(e: &EyeParams, g: &MffrGeometry, far_from_head: Mat4, cant: f32) {
        let f = g.far_fov;
        let tol = 1e-5;
        for eye in Eye::BOTH {
            let fov = e.fov(eye);
            // In f64 throughout: the poses and tangents widened, every point computed anew, so
            // the check owes nothing to the f32 arithmetic it checks.
            let head_from_eye = e.head_from_eye(eye).as_dmat4();
            let far_from_head = far_from_head.as_dmat4();
            let [left, right, up, down] = fov.as_array().map(f64::from);
            let (split, far) = (g.split_m as f64, g.far as f64);
            let n = 8;
            for i in 0..=n {
                for j in 0..=n {
                    for s in [split, 0.5 * (split + far), far] {
                        let x = -left + (left + right) * i as f64 / n as f64;
                        let y = -down + (up + down) * j as f64 / n as f64;
                        let p = head_from_eye.transform_point3(glam::DVec3::new(x * s, y * s, -s));
                        let q = far_from_head.transform_point3(p);
                        let (qx, qy, qz) = (q.x, q.y, q.z);
                        let depth = -qz;
                        assert!(
                            depth >= g.far_near as f64 * (1.0 - 1e-6),
                            "cant {cant}: {q}"
                        );
                        let (tx, ty) = (qx / depth, qy / depth);
                        assert!(
                            tx >= -(f.left as f64) - tol
                                && tx <= f.right as f64 + tol
                                && ty >= -(f.down as f64) - tol
                                && ty <= f.up as f64 + tol,
                            "cant {cant}, {eye:?}: tangent ({tx}, {ty}) outside {f:?}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn reprojection_maps_a_views_pixel_to_where_the_far_view_sees_its_point() {
        let e = eyes(10.0, HmdProfile::by_name("rift-cv1").unwrap().left_fov);
        let world_from_head = Mat4::from_rotation_translation(
            glam::Quat::from_euler(glam::EulerRot::YXZ, 0.7, -0.2, 0.1),
            Vec3::new(3.0, 1.7, -8.0),
        );
        let g = MffrGeometry::resolve(
            MffrConfig::default(),
            &e,
            Resolution::square(512),
            0.05,
            500.0,
        )
        .unwrap()
        .unwrap();
        let far_view = far_view_from_head(MffrVariant::Centre, &e, 0) * world_from_head.inverse();
        let far_view_proj = reverse_z_projection(g.far_fov, g.far_near, g.far) * far_view;
        for eye in Eye::BOTH {
            let world_from_eye = world_from_head * e.head_from_eye(eye);
            let r = FarReprojection::new(world_from_eye, e.fov(eye), far_view_proj);
            let view_proj =
                reverse_z_projection(e.fov(eye), 0.05, 500.0) * world_from_eye.inverse();
            for (x, y, s) in [(0.1, -0.3, 40.0), (-0.8, 0.6, 120.0), (0.9, 0.9, 300.0)] {
                let p = world_from_eye.transform_point3(Vec3::new(x * s, y * s, -s));
                let clip = view_proj * p.extend(1.0);
                let ndc = glam::Vec2::new(clip.x / clip.w, clip.y / clip.w);
                let far_clip = far_view_proj * p.extend(1.0);
                let want = glam::Vec2::new(far_clip.x / far_clip.w, far_clip.y / far_clip.w);
                let got = r.far_ndc(ndc, s);
                assert!((got - want).length() < 1e-4, "{eye:?}: {got} vs {want}");
            }
        }
    }
}
