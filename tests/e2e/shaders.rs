use std::process::Command;

/// Every shader the renderer and the judge can load passes `spirv-val` for Vulkan 1.1.
#[test]
fn every_shader_passes_spirv_val() {
    let dir = std::env::temp_dir().join(format!("foveate-spirv-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for shader in foveate::shaders::ALL
        .iter()
        .chain(foveate::shaders::COMPUTE)
    {
        let path = dir.join(shader.name);
        std::fs::write(&path, shader.spirv).unwrap();
        let out = Command::new("spirv-val")
            .arg("--target-env")
            .arg("vulkan1.1")
            .arg(&path)
            .output()
            .expect("spirv-val runs (apt-get install spirv-tools)");
        assert!(
            out.status.success(),
            "{}: {}",
            shader.name,
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let _ = std::fs::remove_dir_all(dir);
}
