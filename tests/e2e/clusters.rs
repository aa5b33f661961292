//! Clusters on the GPU: a frame that culls the atrium's large meshes cluster by cluster (its
//! floor, its vases) is the frame that draws them whole, pixel for pixel, in both fovea layouts,
//! with stereo culling and with MFFR's near and far sets; and the fovea pass assembles fewer
//! primitives. Mutations: a cone turned around (`faces_away` reading `-axis`) drops visible
//! clusters and changes pixels; a frustum test against half the bounding sphere does too; a
//! cluster test that keeps everything leaves the primitive count unchanged.

use foveate::cull::Strategy;
use foveate::foveation::FoveationConfig;
use foveate::mffr::{MffrConfig, MffrOrder, MffrVariant, SplitDistance};
use foveate::plan::{CullConfig, FoveaLayout, RenderConfig, Resolution, StereoMode};
use foveate::scene::{atrium_scene, ClusterSettings, Scene};
use foveate_tests::{gpu, render_at};
use glam::Vec2;

fn scenes() -> (Scene, Scene) {
    let whole = atrium_scene();
    let clustered = whole
        .clone()
        .with_clusters(ClusterSettings::default())
        .unwrap();
    assert!(
        clustered.cluster_counts().0 > 0,
        "the atrium's floor is clustered"
    );
    (whole, clustered)
}

fn base() -> RenderConfig {
    RenderConfig {
        resolution: Some(Resolution::square(128)),
        msaa: 4,
        count_fragments: false,
        ..RenderConfig::default()
    }
}

fn foveated(layout: FoveaLayout) -> RenderConfig {
    RenderConfig {
        foveation: Some(FoveationConfig {
            ratio: 0.35,
            ..FoveationConfig::single_frame()
        }),
        fovea_layout: layout,
        ..base()
    }
}

#[test]
fn clustered_frames_equal_whole_mesh_frames() {
    let gpu = gpu();
    let (whole, clustered) = scenes();
    let gaze = Vec2::new(0.3, -0.2);
    let culled = |stereo| RenderConfig {
        stereo,
        culling: Some(CullConfig {
            strategy: Strategy::Superfrustum,
            draw_distance: 100.0,
        }),
        ..base()
    };
    let mffr = RenderConfig {
        mffr: Some(MffrConfig {
            split: SplitDistance::Metres(6.0),
            order: MffrOrder::NearFirst,
            variant: MffrVariant::Centre,
            ..MffrConfig::default()
        }),
        ..base()
    };
    let configs = [
        ("one-pass fovea", foveated(FoveaLayout::OnePass)),
        ("two-pass fovea", foveated(FoveaLayout::TwoPass)),
        (
            "multiview, superfrustum culling",
            culled(StereoMode::Multiview),
        ),
        (
            "two-pass, superfrustum culling",
            culled(StereoMode::TwoPass),
        ),
        ("MFFR near and far", mffr),
    ];
    let mut culled_frames = 0;
    for (what, config) in configs {
        let plan = foveate::plan(&clustered, &config, gpu.caps()).unwrap();
        let reference = render_at(&gpu, &whole, &config, gaze);
        let image = render_at(&gpu, &clustered, &config, gaze);
        assert!(image == reference, "{what}: clusters changed pixels");
        let clusters = plan
            .clusters
            .expect("a clustered scene's plan has clusters");
        culled_frames += clusters.culled() as u32;
        // Only lavapipe 22.3's multiview bug keeps clusters whole.
        let multiview = plan.passes.iter().any(|p| p.view_mask.count_ones() > 1);
        assert_eq!(
            clusters.culled(),
            !(multiview && gpu.caps().quirks.multiview_clipping_drops_views),
            "{what}: {:?}",
            clusters.drawn_whole
        );
    }
    assert!(culled_frames > 0, "some frame culled clusters");
}

/// Culled clusters are not drawn: the two-pass fovea layout's fovea pass assembles fewer
/// primitives than with whole meshes (pipeline statistics), its periphery pass (every instance,
/// uncut) the same; two-pass stereo with superfrustum culling assembles fewer in each eye's
/// pass. Where lavapipe 22.3's multiview bug keeps clusters whole, the fovea layout is skipped.
#[test]
fn culled_clusters_assemble_fewer_primitives() {
    let gpu = gpu();
    let (whole, clustered) = scenes();
    let gaze = [Vec2::new(0.3, -0.2); 2];
    let count = |scene: &Scene, config: &RenderConfig| {
        let stats = foveate::render::counting_frame(&gpu, scene, config, gaze, scene.head)
            .expect("counting frame");
        foveate_tests::assert_validation_clean(&gpu);
        stats
            .pass_statistics
            .iter()
            .map(|p| p.assembled)
            .collect::<Vec<_>>()
    };
    let stereo = RenderConfig {
        stereo: StereoMode::TwoPass,
        culling: Some(CullConfig {
            strategy: Strategy::Superfrustum,
            draw_distance: 100.0,
        }),
        ..base()
    };
    let (before, after) = (count(&whole, &stereo), count(&clustered, &stereo));
    if before.is_empty() {
        eprintln!("skipped: this device has no pipeline statistics");
        return;
    }
    for (pass, (a, b)) in after.iter().zip(&before).enumerate() {
        assert!(
            a < b,
            "two-pass stereo pass {pass}: {a} primitives with clusters, {b} whole"
        );
    }
    let config = foveated(FoveaLayout::TwoPass);
    let plan = foveate::plan(&clustered, &config, gpu.caps()).unwrap();
    if !plan.clusters.is_some_and(|c| c.culled()) {
        eprintln!("fovea layout skipped: clusters drawn whole on this driver");
        return;
    }
    let (before, after) = (count(&whole, &config), count(&clustered, &config));
    let fovea = plan.passes.iter().position(|p| p.first_view == 2).unwrap();
    let periphery = fovea - 1;
    assert!(
        after[fovea] < before[fovea],
        "fovea pass: {} primitives with clusters, {} whole",
        after[fovea],
        before[fovea]
    );
    assert_eq!(after[periphery], before[periphery], "periphery pass");
}
