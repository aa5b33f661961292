//! The price on recorded statistics and counts (no lavapipe reports statistics), against a pass
//! computed by hand.

use super::*;
use crate::gpu::{ShaderExecutable, ShaderStatistic, StatisticValue};
use crate::plan::CountedStep;
use ash::vk;

fn executable(name: &str, stages: vk::ShaderStageFlags, instructions: u64) -> ShaderExecutable {
    ShaderExecutable {
        name: name.into(),
        description: String::new(),
        stages,
        subgroup_size: 128,
        statistics: vec![ShaderStatistic {
            name: "Instruction Count".into(),
            description: String::new(),
            value: StatisticValue::Uint(instructions),
        }],
    }
}

/// A scene pass priced with the statistics turnip recorded for the lit scene shader on the
/// Adreno 650 (fragment shader 1171 instructions, vertex shader 135, the binning pass's 106):
/// 1 M fragments and 30 k triangles, 8 MB moved. By hand, on 768 lanes at 587 MHz:
/// (1e6 × 1171 + 90 000 × 241) / 450.816e9 s = 2.6457 ms of ALU; 8e6 / 44e9 s = 0.18182 ms of
/// memory. Mutation: the binning shader left out (2.6246 ms), or the bound taken as the sum,
/// fails it.
#[test]
fn a_pass_costs_its_larger_bound_computed_by_hand() {
    let work = [PassWork {
        name: "scene",
        steps: vec![StepWork {
            step: CountedStep::Scene,
            fragments: 1_000_000,
            fragment_instructions: 1171.0,
            vertices: 90_000,
            vertex_instructions: 241.0,
        }],
        bytes: 8_000_000,
    }];
    let price = ADRENO_650.price(&work, 0);
    let pass = &price.passes[0];
    assert!((pass.alu_ms - 2.6457).abs() < 1e-4, "{pass:?}");
    assert!((pass.memory_ms - 0.18182).abs() < 1e-4, "{pass:?}");
    assert_eq!(pass.bound(), Bound::Alu);
    assert!((price.ms() - pass.alu_ms).abs() < 1e-12);
    // A pass that moves more than it computes is memory-bound.
    let heavy = [PassWork {
        bytes: 400_000_000,
        ..work[0].clone()
    }];
    let price = ADRENO_650.price(&heavy, 44_000_000);
    assert_eq!(price.passes[0].bound(), Bound::Memory);
    assert!(
        (price.ms() - (400.0 / 44.0 + 1.0)).abs() < 1e-9,
        "{price:?}"
    );
    // The instruction counts the steps are priced with: the vertex and binning shaders summed.
    let executables = [
        executable("VS", vk::ShaderStageFlags::VERTEX, 135),
        executable("FS", vk::ShaderStageFlags::FRAGMENT, 1171),
        executable("Binning VS", vk::ShaderStageFlags::VERTEX, 106),
    ];
    assert_eq!(
        work::instructions(&executables, vk::ShaderStageFlags::VERTEX),
        Some(241.0)
    );
    assert_eq!(
        work::instructions(&executables, vk::ShaderStageFlags::FRAGMENT),
        Some(1171.0)
    );
    assert_eq!(
        work::instructions(&executables[..1], vk::ShaderStageFlags::FRAGMENT),
        None
    );
}

/// The 740 is priced at 2.5 times the 650's ALU rate, as Qualcomm's launch figure says.
#[test]
fn the_740_has_two_and_a_half_times_the_650s_alu_rate() {
    let ratio = ADRENO_740.instructions_per_second() / ADRENO_650.instructions_per_second();
    assert!((ratio - 2.5).abs() < 1e-9, "{ratio}");
}

/// Each pass's bytes and the display's read add up to the plan's traffic, stereo and the
/// default foveation (a history loaded, sampled and stored; a depth kept and sampled). Mutation:
/// a pass's sampled images left out, or a stencil the pass does not keep counted, fails it.
#[test]
fn the_passes_bytes_add_up_to_the_frames() {
    use crate::foveation::FoveationConfig;
    use crate::plan::{DeviceCaps, RenderConfig, Resolution, StereoMode};
    let scene = crate::scene::default_scene();
    let caps = DeviceCaps::generic();
    for foveation in [None, Some(FoveationConfig::default())] {
        let config = RenderConfig {
            stereo: StereoMode::Multiview,
            resolution: Some(Resolution::square(256)),
            foveation,
            ..RenderConfig::default()
        };
        let plan = crate::plan(&scene, &config, &caps).unwrap();
        let passes: u64 = plan.pass_traffic_bytes().iter().sum();
        assert_eq!(
            passes + plan.display_read_bytes(),
            plan.external_traffic_bytes()
        );
        assert!(plan.pass_traffic_bytes().iter().all(|&b| b > 0));
    }
}
