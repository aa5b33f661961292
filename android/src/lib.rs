//! Android glue for foveate: on Android, a NativeActivity that renders the default scene
//! headless with the core renderer and logs frame times (the APK demo builds on it). On every
//! other target this crate is an empty shell; everything it drives lives in `foveate` and is
//! tested on the host.

#[cfg(target_os = "android")]
mod activity;
