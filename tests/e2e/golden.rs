use foveate::plan::{RenderConfig, Resolution, StereoMode};
use foveate::scene::{atrium_scene, default_scene};
use foveate_tests::{assert_matches_golden, gpu, render};

/// The default scene at 128²/eye against committed references (re-bless with
/// `FOVEATE_BLESS=1 cargo test -p foveate-tests --test e2e golden`).
#[test]
fn default_scene_matches_golden_images() {
    let gpu = gpu();
    let scene = default_scene();
    for msaa in [1, 4] {
        let config = RenderConfig {
            stereo: StereoMode::Multiview,
            msaa,
            resolution: Some(Resolution::square(128)),
            ..RenderConfig::default()
        };
        let (image, _) = render(&gpu, &scene, &config);
        assert_matches_golden(
            &format!("default-index-128-msaa{msaa}"),
            &image.side_by_side(),
            0.99,
        );
    }
}

/// The lit atrium (PBR materials, procedural textures, lights) at 96²/eye against its
/// committed reference. Mutation: a texture, the normal map's orientation or a light's falloff
/// changed fails it.
#[test]
fn lit_atrium_matches_golden_image() {
    let gpu = gpu();
    let scene = atrium_scene();
    let config = RenderConfig {
        msaa: 4,
        resolution: Some(Resolution::square(96)),
        ..RenderConfig::default()
    };
    let (image, _) = render(&gpu, &scene, &config);
    assert_matches_golden("atrium-lit-index-96-msaa4", &image.side_by_side(), 0.98);
}
