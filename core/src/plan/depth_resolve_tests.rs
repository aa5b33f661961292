//! An accumulated periphery with MSAA: its depth is resolved to one sample in its own pass, for
//! the output pass's reprojection, and the multisampled depth never leaves the tile.

use super::tests::*;
use super::*;
use crate::foveation::{FoveationConfig, TemporalConfig};

fn accumulated(periphery_msaa: u32) -> RenderConfig {
    RenderConfig {
        foveation: foveated(true).foveation.map(|f| FoveationConfig {
            periphery_density: Some(0.25),
            periphery_msaa: Some(periphery_msaa),
            periphery_temporal: Some(TemporalConfig::default()),
            ..f
        }),
        fovea_layout: FoveaLayout::Auto,
        ..foveated(true)
    }
}

/// At 4× the periphery pass resolves its depth into a single-sample image that the depth pair
/// holds (stored, sampled, no stencil), while the multisampled depth stays transient: the frame
/// moves no more bytes than at 1×, where nothing is resolved; asked for no sample count, the
/// periphery is 1×. A device that cannot resolve depth refuses it, naming the field, the count and
/// the device. Mutations: the resolve left out (the pair then holds the multisampled depth,
/// sampled), the refusal gone, or the unasked default the frame's 4×, fail it.
#[test]
fn a_multisampled_periphery_resolves_its_depth_in_its_pass() {
    let single = planned(&accumulated(1));
    assert!(single.passes.iter().all(|p| p.depth_resolve.is_none()));
    // Asked for no sample count, an accumulated periphery is 1× in a 4× frame: its jitter
    // antialiases it (4× measured no better along the walk at the Quest Pro's panel).
    let unasked = accumulated(1);
    let unasked = RenderConfig {
        foveation: unasked.foveation.map(|f| FoveationConfig {
            periphery_msaa: None,
            ..f
        }),
        ..unasked
    };
    assert_eq!(unasked.msaa, 4);
    let unasked = planned(&unasked);
    assert_eq!(
        unasked.attachments[unasked.passes[0].color.attachment].samples,
        1
    );
    assert!(unasked.passes.iter().all(|p| p.depth_resolve.is_none()));

    let plan = planned(&accumulated(4));
    let periphery = &plan.passes[0];
    let depth = periphery.depth.expect("the periphery pass has depth");
    let resolved = periphery
        .depth_resolve
        .expect("the depth resolved in the pass");
    let pair = plan.depth_history.expect("the depth pair");
    assert_eq!(pair.written, resolved.attachment);
    assert!(plan.passes[2].samples.contains(&resolved.attachment));
    let ms = &plan.attachments[depth.attachment];
    assert_eq!((ms.samples, ms.transient, ms.sampled), (4, true, false));
    assert_eq!(
        depth.store,
        StoreOp::DontCare,
        "the multisampled depth stays on tile"
    );
    for id in [pair.written, pair.read] {
        let a = &plan.attachments[id];
        assert_eq!(
            (a.samples, a.format, a.sampled, a.transient),
            (1, Format::D32, true, false),
            "{}",
            a.name
        );
        assert_eq!((a.width, a.layers), (ms.width, ms.layers), "{}", a.name);
    }
    assert_eq!(
        (resolved.store, resolved.final_layout),
        (StoreOp::Store, Layout::ShaderReadOnly)
    );
    // The resolve writes at colour attachment output; the output pass waits for it there.
    assert!(plan.passes[2]
        .barriers
        .wait
        .iter()
        .any(|b| b.attachment == resolved.attachment && b.from == Touch::ColourAttachment));
    // On a tile GPU the samples never leave the tile: the frame moves no more bytes than at
    // 1× (less: the resolved depth has no stencil).
    assert!(
        plan.external_traffic_bytes() <= single.external_traffic_bytes(),
        "{} bytes at 4x against {} at 1x",
        plan.external_traffic_bytes(),
        single.external_traffic_bytes()
    );

    let caps = DeviceCaps {
        depth_resolve: false,
        ..caps()
    };
    assert!(plan_of(&accumulated(1), &caps).is_ok());
    let e = plan_of(&accumulated(4), &caps).unwrap_err();
    assert_eq!(e.field, "periphery_msaa");
    let message = e.to_string();
    assert!(
        message.contains('4') && message.contains(&caps.device_name),
        "{message}"
    );
}

fn plan_of(config: &RenderConfig, caps: &DeviceCaps) -> Result<FramePlan, ConfigError> {
    plan(&crate::scene::default_scene(), config, caps)
}
