//! The Android demo of foveate: a NativeActivity presenting the default scene, lit and
//! foveated, through the lens output stage side by side (a phone in a headset), with touch as
//! the gaze and frame times logged once a second.
//!
//! Everything but `activity` compiles and is tested on every host: the lifecycle state machine
//! ([`app`]) and the Vulkan backend it drives ([`vulkan`]). `activity` (Android only) turns
//! `android-activity`'s events into [`app::Event`]s.

#[cfg(target_os = "android")]
mod activity;
pub mod app;
pub mod vulkan;
