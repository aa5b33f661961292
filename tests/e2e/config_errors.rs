use foveate::plan::{RenderConfig, Resolution};
use foveate::scene::default_scene;
use foveate_tests::gpu;

/// Bad configurations against the real device's limits: each error names the field, the value
/// and the limit.
#[test]
fn bad_configs_are_rejected_with_field_value_and_limit() {
    let gpu = gpu();
    let scene = default_scene();
    let base = RenderConfig {
        resolution: Some(Resolution::square(64)),
        ..RenderConfig::default()
    };
    let cases: Vec<(RenderConfig, &str, &str, &str)> = vec![
        (
            RenderConfig {
                views: Some(5),
                ..base.clone()
            },
            "views",
            "5",
            "at most 4",
        ),
        (
            RenderConfig {
                msaa: 8,
                ..base.clone()
            },
            "msaa",
            "8",
            "1 or 4",
        ),
        (
            RenderConfig {
                msaa: 0,
                ..base.clone()
            },
            "msaa",
            "0",
            "1 or 4",
        ),
        (
            RenderConfig {
                resolution: Some(Resolution::square(0)),
                ..base.clone()
            },
            "resolution",
            "0x0",
            "1..=",
        ),
        (
            RenderConfig {
                ipd_m: Some(f32::NAN),
                ..base.clone()
            },
            "ipd",
            "NaN",
            "finite",
        ),
        (
            RenderConfig {
                hmd: "pimax".into(),
                ..base.clone()
            },
            "hmd",
            "pimax",
            "one of index, vive, rift-cv1, quest2, quest-pro, quest3",
        ),
    ];
    for (config, field, value, limit) in cases {
        let e = foveate::plan(&scene, &config, gpu.caps()).expect_err(field);
        assert_eq!((e.field, e.value.as_str()), (field, value), "{e}");
        assert!(e.limit.contains(limit), "`{e}` should mention `{limit}`");
        assert!(
            e.to_string().contains(field) && e.to_string().contains(value),
            "{e}"
        );
    }
    // The device's own limit shows up when it is the tighter one.
    let mut caps = gpu.caps().clone();
    caps.framebuffer_sample_counts = 1;
    let e = foveate::plan(&scene, &RenderConfig { msaa: 4, ..base }, &caps).unwrap_err();
    assert!(e.limit.contains("it supports 1"), "{e}");
}

/// Lavapipe offers 1 and 4 samples only, so MSAA 8 is refused there.
#[test]
fn msaa_8_is_refused_on_this_device_when_unsupported() {
    let gpu = gpu();
    if gpu.caps().supports_samples(8) {
        return; // A real GPU may support 8; foveate still refuses anything but 1 or 4 above.
    }
    let config = RenderConfig {
        msaa: 8,
        resolution: Some(Resolution::square(64)),
        ..RenderConfig::default()
    };
    let e = foveate::plan(&default_scene(), &config, gpu.caps()).unwrap_err();
    assert!(!e.limit.contains('8'), "{e}");
}
