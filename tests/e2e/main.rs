//! End-to-end tests on a real Vulkan device (lavapipe in CI) with validation on: any validation
//! message fails the test that caused it.

mod caches;
mod clusters;
mod config_errors;
mod culling;
mod engine_device;
mod external_output;
mod foveation;
mod fragment_counter;
mod frames_in_flight;
mod gltf;
mod golden;
mod gpu_flicker;
mod history_outcomes;
mod judge;
mod judge_engine_images;
mod latency;
mod lod;
mod mffr;
mod moving_instances;
mod output_images;
mod perception;
mod prefilter;
mod quirks;
mod radial_density;
mod robustness;
mod shaders;
mod stereo;
mod temporal;
mod temporal_history_at;
mod temporal_lens;
mod temporal_motion;
mod temporal_msaa;
mod temporal_new_sample;
mod temporal_reach;
mod zero_cost;
