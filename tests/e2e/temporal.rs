//! Temporal accumulation of the periphery on the GPU: it converges towards a supersampled
//! reference on a still frame, and drops its history where it would ghost (where the fovea
//! covered the periphery before a gaze jump; everywhere after a teleport).

use foveate::foveation::{
    fovea_centre_px, fovea_views, ClipNeighbourhood, FoveationConfig, HistoryAt, HistoryFilter,
    HistoryFormat, TemporalConfig,
};
use foveate::metrics::RgbaImage;
use foveate::plan::{FoveaLayout, FramePlan, OutputStage, RenderConfig, Resolution, StereoMode};
use foveate::render::StereoImage;
use foveate::scene::{atrium_scene, Scene};
use foveate::view::Eye;
use foveate_tests::{gpu, linear, render_motion};
use glam::{Mat4, Vec2, Vec3};

const SCREEN: u32 = 128;

pub(crate) fn config(screen: u32, temporal: Option<TemporalConfig>) -> RenderConfig {
    RenderConfig {
        stereo: StereoMode::Multiview,
        msaa: 1,
        resolution: Some(Resolution::square(screen)),
        output: OutputStage::Undistorted,
        fovea_layout: FoveaLayout::Auto,
        foveation: Some(FoveationConfig {
            ratio: 0.35,
            periphery_density: Some(0.5),
            periphery_temporal: temporal,
            ..FoveationConfig::single_frame()
        }),
        ..RenderConfig::default()
    }
}

/// Plans `config` and renders `poses` in order (each a head pose and a gaze), reading back
/// after each frame that `read` asks for.
pub(crate) fn render_sequence(
    gpu: &foveate::gpu::Gpu,
    scene: &Scene,
    config: &RenderConfig,
    poses: &[(Mat4, Vec2)],
    read: impl Fn(usize) -> bool,
) -> (FramePlan, Vec<StereoImage>) {
    let plan = foveate::plan(scene, config, gpu.caps()).unwrap();
    let images = render_motion(gpu, scene, &plan, poses, read);
    (plan, images)
}

/// `image` averaged over `k`×`k` blocks in linear light: a supersampled reference.
pub(crate) fn box_down(image: &RgbaImage, k: u32) -> Vec<[f64; 3]> {
    let (w, h) = (image.width / k, image.height / k);
    let mut out = vec![[0.0; 3]; (w * h) as usize];
    for y in 0..h {
        for x in 0..w {
            let sum = &mut out[(y * w + x) as usize];
            for dy in 0..k {
                for dx in 0..k {
                    let p = image.pixel(x * k + dx, y * k + dy);
                    for c in 0..3 {
                        sum[c] += linear(p[c]) / (k * k) as f64;
                    }
                }
            }
        }
    }
    out
}

/// Where the periphery alone shows: beyond the fovea circle (band included) by two pixels.
pub(crate) fn periphery_only(plan: &FramePlan, gaze: Vec2) -> [Vec<bool>; 2] {
    let g = plan.foveation.unwrap();
    let screen = (plan.eye_resolution.width, plan.eye_resolution.height);
    let fovea = fovea_views(&plan.eyes, g.ratio, [gaze; 2], screen);
    Eye::BOTH.map(|e| {
        let centre = fovea_centre_px(plan.eyes.fov(e), fovea[e.index()], screen);
        (0..screen.1)
            .flat_map(|y| (0..screen.0).map(move |x| (x, y)))
            .map(|(x, y)| {
                let p = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                p.distance(centre) > g.fovea_screen_px / 2.0 + 2.0
            })
            .collect()
    })
}

/// Half a second of the head turning 20°/s from the scene's pose, the gaze ahead: every point
/// of the periphery moves every frame.
pub(crate) fn turning(scene: &Scene) -> Vec<(Mat4, Vec2)> {
    (0..45)
        .map(|f| {
            let angle = (20.0f32 / 90.0 * f as f32).to_radians();
            (scene.head * Mat4::from_rotation_y(angle), Vec2::ZERO)
        })
        .collect()
}

/// The supersampled reference at `pose`: the scene in stereo at 4× the resolution, box-filtered.
pub(crate) fn supersampled(
    gpu: &foveate::gpu::Gpu,
    scene: &Scene,
    pose: (Mat4, Vec2),
) -> [Vec<[f64; 3]>; 2] {
    let stereo = RenderConfig {
        foveation: None,
        resolution: Some(Resolution::square(SCREEN * 4)),
        ..config(SCREEN, None)
    };
    let (_, big) = render_sequence(gpu, scene, &stereo, &[pose], |_| true);
    Eye::BOTH.map(|e| box_down(big[0].eye(e), 4))
}

/// Mean absolute error in linear light against the reference, over `region`, both eyes.
pub(crate) fn periphery_error(
    image: &StereoImage,
    reference: &[Vec<[f64; 3]>; 2],
    region: &[Vec<bool>; 2],
) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for e in Eye::BOTH {
        let img = image.eye(e);
        for y in 0..img.height {
            for x in 0..img.width {
                let i = (y * img.width + x) as usize;
                if !region[e.index()][i] {
                    continue;
                }
                let p = img.pixel(x, y);
                sum += (0..3)
                    .map(|c| (linear(p[c]) - reference[e.index()][i][c]).abs())
                    .sum::<f64>();
                n += 3;
            }
        }
    }
    sum / n as f64
}

/// On a still frame the accumulated periphery approaches the supersampled reference (the
/// scene at 4× the resolution, box-filtered) as frames go by, and ends closer to it than the
/// bilinear periphery does. Negative control in the test: without jitter (a cycle of 1) the
/// history gains nothing from frame to frame. A history of luma alone in a byte converges too.
/// Mutations: the jitter applied with the wrong sign in the shader (samples credited to the
/// wrong pixels), the history never blended, or a luma history decoded as a colour one, fail it.
#[test]
fn accumulation_converges_on_a_still_frame() {
    let gpu = gpu();
    let scene = atrium_scene();
    let stereo = RenderConfig {
        foveation: None,
        resolution: Some(Resolution::square(SCREEN * 4)),
        ..config(SCREEN, None)
    };
    let (_, big) = render_sequence(&gpu, &scene, &stereo, &[(scene.head, Vec2::ZERO)], |_| true);
    let reference = Eye::BOTH.map(|e| box_down(big[0].eye(e), 4));
    let frames = 24;
    let still = vec![(scene.head, Vec2::ZERO); frames];
    let error = |temporal| {
        let (plan, images) =
            render_sequence(&gpu, &scene, &config(SCREEN, temporal), &still, |f| {
                f == 0 || f == frames - 1
            });
        let region = periphery_only(&plan, Vec2::ZERO);
        images
            .iter()
            .map(|i| periphery_error(i, &reference, &region))
            .collect::<Vec<f64>>()
    };
    let bilinear = error(None);
    let accumulated = error(Some(TemporalConfig::default()));
    let unjittered = error(Some(TemporalConfig {
        jitter_cycle: 1,
        ..Default::default()
    }));
    let luma = error(Some(TemporalConfig {
        history_format: HistoryFormat::Luma,
        ..Default::default()
    }));
    eprintln!("periphery error (first, last frame): bilinear {bilinear:?}, accumulated {accumulated:?}, unjittered {unjittered:?}, luma {luma:?}");
    assert!(
        luma[1] < 0.85 * luma[0] && luma[1] < bilinear[1],
        "a luma history converges too: {luma:?} against {bilinear:?}"
    );
    assert!(
        accumulated[0] <= bilinear[0],
        "the first frame starts from the bilinear periphery (its textures at the screen's \
         detail): {accumulated:?} vs {bilinear:?}"
    );
    assert!(
        accumulated[1] < 0.85 * accumulated[0],
        "the error falls with frames: {accumulated:?}"
    );
    assert!(
        accumulated[1] < 0.75 * bilinear[1],
        "{accumulated:?} vs {bilinear:?}"
    );
    assert!(
        unjittered[1] > 0.9 * unjittered[0],
        "negative control: without jitter nothing new arrives: {unjittered:?}"
    );
}

/// Pixels more than one 8-bit level apart in some channel, over `region` (both eyes).
fn differing(a: &StereoImage, b: &StereoImage, region: &[Vec<bool>; 2]) -> (usize, usize) {
    differing_by(a, b, region, 1)
}

/// Pixels more than `levels` 8-bit levels apart in some channel, over `region` (both eyes).
pub(crate) fn differing_by(
    a: &StereoImage,
    b: &StereoImage,
    region: &[Vec<bool>; 2],
    levels: u8,
) -> (usize, usize) {
    let (mut off, mut n) = (0, 0);
    for e in Eye::BOTH {
        let (x, y) = (a.eye(e), b.eye(e));
        for py in 0..x.height {
            for px in 0..x.width {
                if !region[e.index()][(py * x.width + px) as usize] {
                    continue;
                }
                n += 1;
                let (p, q) = (x.pixel(px, py), y.pixel(px, py));
                off += (0..3).any(|c| p[c].abs_diff(q[c]) > levels) as usize;
            }
        }
    }
    (off, n)
}

/// After a gaze jump, where the fovea was, the periphery starts from what the fovea showed
/// there (the history keeps it over the periphery's hole), not from the hole's sky clamped into
/// the scene nor from nothing: against the scene at 4× the resolution, its error there keeps
/// more than half of what the fovea gained over a fresh renderer's bilinear periphery. No
/// jitter, so only the history differs. Negative control in the test: the fovea, in the frame
/// before the jump, is closer to the reference there than a fresh periphery (there is a gain
/// to keep). Mutation run: the output pass keeping nothing over the hole (as before) makes the
/// old hole a fresh frame's, and fails it.
#[test]
fn a_gaze_jump_starts_the_old_fovea_from_what_it_showed() {
    let (fovea, jumped, fresh) = gaze_jump(HistoryAt::Output);
    assert!(
        jumped < 0.5 * (fovea + fresh),
        "after the jump the old hole's error is {jumped}: the fovea's was {fovea}, a fresh \
         frame's is {fresh}"
    );
}

/// Over the old hole, the old fovea's error (the frame before a gaze jump), the error after
/// the jump, and a fresh renderer's there, the history kept `history_at`; asserts the negative
/// control (the fovea was closer to the reference there than a fresh periphery).
pub(crate) fn gaze_jump(history_at: HistoryAt) -> (f64, f64, f64) {
    let gpu = gpu();
    let scene = atrium_scene();
    let config = config(
        SCREEN,
        Some(TemporalConfig {
            jitter_cycle: 1,
            history_at,
            ..Default::default()
        }),
    );
    let stereo = RenderConfig {
        foveation: None,
        resolution: Some(Resolution::square(SCREEN * 4)),
        ..config.clone()
    };
    let (_, big) = render_sequence(&gpu, &scene, &stereo, &[(scene.head, Vec2::ZERO)], |_| true);
    let reference = Eye::BOTH.map(|e| box_down(big[0].eye(e), 4));
    let (from, to) = (Vec2::new(-0.3, 0.0), Vec2::new(0.3, 0.0));
    let mut poses = vec![(scene.head, from); 6];
    poses.push((scene.head, to));
    let (plan, frames) = render_sequence(&gpu, &scene, &config, &poses, |f| f >= 5);
    let (_, fresh) = render_sequence(&gpu, &scene, &config, &[(scene.head, to)], |_| true);
    // The old hole (the accumulation's), shrunk by two pixels, outside the new fovea.
    let g = plan.foveation.unwrap();
    let screen = (SCREEN, SCREEN);
    let old = fovea_views(&plan.eyes, g.ratio, [from; 2], screen);
    let new_periphery = periphery_only(&plan, to);
    let hole = Eye::BOTH.map(|e| {
        let centre = fovea_centre_px(plan.eyes.fov(e), old[e.index()], screen);
        let radius = g.accumulated_hole_px / 2.0 - 2.0;
        (0..SCREEN * SCREEN)
            .map(|i| {
                let p = Vec2::new((i % SCREEN) as f32 + 0.5, (i / SCREEN) as f32 + 0.5);
                p.distance(centre) < radius && new_periphery[e.index()][i as usize]
            })
            .collect::<Vec<bool>>()
    });
    let n: usize = hole.iter().flatten().filter(|&&h| h).count();
    assert!(n > 100, "the old hole covers {n} pixels");
    let error = |image| periphery_error(image, &reference, &hole);
    let (fovea, jumped, fresh) = (error(&frames[0]), error(&frames[1]), error(&fresh[0]));
    eprintln!("old hole's error: the fovea's {fovea}, after the jump {jumped}, fresh {fresh}");
    assert!(
        fovea < fresh,
        "negative control: the fovea ({fovea}) is no closer than the periphery ({fresh})"
    );
    (fovea, jumped, fresh)
}

/// A teleport is a cut: the frame after it is exactly a fresh renderer's first frame there.
/// Negative control in the test: with cut detection off, the reprojected history survives the
/// teleport where depths happen to agree and the frame differs.
#[test]
fn a_teleport_drops_the_history() {
    let gpu = gpu();
    let scene = atrium_scene();
    let elsewhere = scene.head
        * Mat4::from_translation(Vec3::new(1.0, 0.0, -1.5))
        * Mat4::from_rotation_y(40f32.to_radians());
    let mut poses = vec![(scene.head, Vec2::ZERO); 6];
    poses.push((elsewhere, Vec2::ZERO));
    let unjittered = TemporalConfig {
        jitter_cycle: 1,
        ..Default::default()
    };
    let run = |t: TemporalConfig| {
        let config = config(SCREEN, Some(t));
        let (plan, after) = render_sequence(&gpu, &scene, &config, &poses, |f| f == 6);
        let (_, fresh) =
            render_sequence(&gpu, &scene, &config, &[(elsewhere, Vec2::ZERO)], |_| true);
        let region = periphery_only(&plan, Vec2::ZERO);
        differing(&after[0], &fresh[0], &region)
    };
    let (off, n) = run(unjittered);
    assert_eq!(
        off, 0,
        "{off} of {n} periphery pixels differ from a fresh frame"
    );
    let (kept, n) = run(TemporalConfig {
        cut_distance_m: f32::INFINITY,
        cut_angle_deg: f32::INFINITY,
        ..unjittered
    });
    assert!(
        kept > n / 100,
        "negative control: without the cut only {kept} of {n} pixels kept history"
    );
}

/// With the head still the disocclusion test drops no history at edges: between two settled
/// frames fewer than 1 in 100 periphery pixels jump by more than 8 levels (a dropped history
/// restarts from the bilinear periphery: a jump, not the jitter's residue), though the jitter
/// puts a sample's own depth texel across every edge. Negative control in the test: the
/// measure sees the accumulation settle (the first frame against the last: over 1 in 100).
/// Mutation run: testing only the point's own texel also where nothing moved (`moved = true`
/// in the shader) fails it, 1,305 of 28,998 pixels jumping against 55.
#[test]
fn a_still_head_keeps_its_history_at_edges() {
    let gpu = gpu();
    let scene = atrium_scene();
    let frames = 24;
    let still = vec![(scene.head, Vec2::ZERO); frames];
    let (plan, images) = render_sequence(
        &gpu,
        &scene,
        &config(SCREEN, Some(TemporalConfig::default())),
        &still,
        |f| f == 0 || f >= frames - 2,
    );
    let region = periphery_only(&plan, Vec2::ZERO);
    let (settling, n) = differing_by(&images[0], &images[2], &region, 8);
    let (jumps, _) = differing_by(&images[1], &images[2], &region, 8);
    eprintln!("still head: {jumps} of {n} periphery pixels jump; settling: {settling}");
    assert!(
        settling * 100 > n,
        "negative control: from the first frame to the last only {settling} of {n} pixels \
         change by more than 8 levels"
    );
    assert!(
        jumps * 100 < n,
        "{jumps} of {n} periphery pixels jump by more than 8 levels between settled still \
         frames"
    );
}

/// Mean change of the 8-bit channels between `a` and `b` over `region` (both eyes).
fn mean_change(a: &StereoImage, b: &StereoImage, region: &[Vec<bool>; 2]) -> f64 {
    let (mut sum, mut n) = (0u64, 0u64);
    for e in Eye::BOTH {
        let (x, y) = (a.eye(e), b.eye(e));
        for (i, _) in region[e.index()].iter().enumerate().filter(|(_, &r)| r) {
            let (px, py) = (i as u32 % x.width, i as u32 / x.width);
            let (p, q) = (x.pixel(px, py), y.pixel(px, py));
            sum += (0..3).map(|c| p[c].abs_diff(q[c]) as u64).sum::<u64>();
            n += 3;
        }
    }
    sum as f64 / n.max(1) as f64
}

/// Where nothing moved a settled pixel takes new samples at the still blend, and the jitter's
/// shimmer falls with it: between two settled still frames the periphery changes less at ⅟16
/// than at ⅛ (under three quarters as much). Where the head's motion moves every point (a
/// head turning 60°/s) the still blend changes nothing: the frames are the same to the bit.
/// Negative control in the test: the shimmer is there to fall (settled still frames differ).
/// Mutation runs: the shader taking the blend everywhere fails the first half; the still
/// blend everywhere, the second.
#[test]
fn the_still_blend_sets_the_shimmer_only_where_nothing_moved() {
    let gpu = gpu();
    let scene = atrium_scene();
    let frames = 24;
    let with = |still_blend: f32, poses: &[(Mat4, Vec2)]| {
        let t = TemporalConfig {
            still_blend,
            ..TemporalConfig::default()
        };
        let last = poses.len() - 1;
        render_sequence(&gpu, &scene, &config(SCREEN, Some(t)), poses, |f| {
            f + 1 >= last
        })
    };
    let still = vec![(scene.head, Vec2::ZERO); frames];
    let (plan, eighth) = with(0.125, &still);
    let (_, sixteenth) = with(0.0625, &still);
    let region = periphery_only(&plan, Vec2::ZERO);
    let shimmer = |i: &[StereoImage]| mean_change(&i[0], &i[1], &region);
    let (at_eighth, at_sixteenth) = (shimmer(&eighth), shimmer(&sixteenth));
    eprintln!("shimmer (mean 8-bit change): at 1/8 {at_eighth:.4}, at 1/16 {at_sixteenth:.4}");
    assert!(
        at_eighth > 0.01,
        "negative control: settled still frames barely change ({at_eighth})"
    );
    assert!(
        at_sixteenth < 0.75 * at_eighth,
        "the still blend of 1/16 leaves the shimmer at {at_sixteenth} (1/8: {at_eighth})"
    );
    let turn: Vec<_> = (0..frames)
        .map(|f| {
            let angle = (60.0f32 / 90.0 * f as f32).to_radians();
            (scene.head * Mat4::from_rotation_y(angle), Vec2::ZERO)
        })
        .collect();
    let (_, a) = with(0.125, &turn);
    let (_, b) = with(0.0625, &turn);
    assert!(a[1] == b[1], "turning, the still blend changes the image");
}

/// Where the head's motion moves every point, a history resampled with Catmull-Rom stays
/// sharper than one resampled bilinearly frame after frame: after half a second of a head
/// turning 20°/s its periphery lies closer to the supersampled reference at that pose. With
/// the head still the point lies on a history pixel, and the two filters give the same image
/// to the bit. Mutation run: the sharp read skipped (the filter ignored) gives the bilinear error to
/// the fifth decimal, and fails.
#[test]
fn catmull_rom_keeps_a_turning_history_sharper() {
    let gpu = gpu();
    let scene = atrium_scene();
    let turn = turning(&scene);
    let reference = supersampled(&gpu, &scene, turn[turn.len() - 1]);
    let with = |filter: HistoryFilter, poses: &[(Mat4, Vec2)]| {
        let t = TemporalConfig {
            filter,
            ..TemporalConfig::default()
        };
        render_sequence(&gpu, &scene, &config(SCREEN, Some(t)), poses, |f| {
            f == poses.len() - 1
        })
    };
    let (plan, bilinear) = with(HistoryFilter::Bilinear, &turn);
    let (_, sharp) = with(HistoryFilter::CatmullRom, &turn);
    let region = periphery_only(&plan, Vec2::ZERO);
    let (b, s) = (
        periphery_error(&bilinear[0], &reference, &region),
        periphery_error(&sharp[0], &reference, &region),
    );
    eprintln!("periphery error after the turn: bilinear {b:.5}, catmull-rom {s:.5}");
    assert!(s < 0.97 * b, "catmull-rom {s} against bilinear {b}");
    let still = vec![(scene.head, Vec2::ZERO); 12];
    let (_, a) = with(HistoryFilter::Bilinear, &still);
    let (_, c) = with(HistoryFilter::CatmullRom, &still);
    assert!(
        a[0] == c[0],
        "with the head still, catmull-rom changes the image"
    );
}

/// The clip's box from a cross of five texels changes the image only where it is used: where
/// the head's motion moved the point (a turn). With the head still the `Moved` clip uses no box,
/// and the two neighbourhoods give the same image to the bit. Mutation: the neighbourhood not
/// passed to the shader (the constant never set) gives the 3×3's image on the turn, and fails.
#[test]
fn a_cross_neighbourhood_changes_only_what_moved() {
    let gpu = gpu();
    let scene = atrium_scene();
    let with = |neighbourhood: ClipNeighbourhood, poses: &[(Mat4, Vec2)]| {
        let t = TemporalConfig {
            neighbourhood,
            ..TemporalConfig::default()
        };
        render_sequence(&gpu, &scene, &config(SCREEN, Some(t)), poses, |f| {
            f == poses.len() - 1
        })
        .1
    };
    let turn = turning(&scene);
    let (square, cross) = (
        with(ClipNeighbourhood::Square, &turn),
        with(ClipNeighbourhood::Cross, &turn),
    );
    assert!(square[0] != cross[0], "turning, the cross changes nothing");
    let still = vec![(scene.head, Vec2::ZERO); 12];
    let (square, cross) = (
        with(ClipNeighbourhood::Square, &still),
        with(ClipNeighbourhood::Cross, &still),
    );
    assert!(
        square[0] == cross[0],
        "with the head still, the cross changes the image"
    );
}

/// Where the head's motion moves every point, the history is resampled every frame and blurs
/// with each resample; a new sample blended in at the default moving blend (0.35) keeps fewer
/// resamples in the image than ⅛ does, so after half a second of a head turning 20°/s the
/// periphery lies closer to the supersampled reference. With the head still the moving blend
/// is never used (the still blend is), and the two give the same image to the bit. Mutation
/// runs: the default put back at ⅛ (the two configurations then equal) fails the first half;
/// the shader taking the moving blend everywhere, the second.
#[test]
fn the_moving_blend_keeps_a_turning_history_sharper() {
    let gpu = gpu();
    let scene = atrium_scene();
    let turn = turning(&scene);
    let reference = supersampled(&gpu, &scene, turn[turn.len() - 1]);
    let with = |t: TemporalConfig, poses: &[(Mat4, Vec2)]| {
        render_sequence(&gpu, &scene, &config(SCREEN, Some(t)), poses, |f| {
            f == poses.len() - 1
        })
    };
    let default = TemporalConfig::default();
    let eighth = TemporalConfig {
        blend: 0.125,
        ..default
    };
    let (plan, at_default) = with(default, &turn);
    let (_, at_eighth) = with(eighth, &turn);
    let region = periphery_only(&plan, Vec2::ZERO);
    let (d, e) = (
        periphery_error(&at_default[0], &reference, &region),
        periphery_error(&at_eighth[0], &reference, &region),
    );
    eprintln!(
        "periphery error after the turn: blend {} {d:.5}, 1/8 {e:.5}",
        default.blend
    );
    assert!(
        d < 0.97 * e,
        "blend {}: {d} against 1/8's {e}",
        default.blend
    );
    let still = vec![(scene.head, Vec2::ZERO); 12];
    let (_, a) = with(default, &still);
    let (_, b) = with(eighth, &still);
    assert!(
        a[0] == b[0],
        "with the head still, the moving blend changes the image"
    );
}
