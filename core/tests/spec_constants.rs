//! Specialisation-constant ids are declared once, in `plan::Constant`; the GLSL declares them
//! again (`layout(constant_id = N) const TYPE NAME`). This reads every shader source and fails
//! where the two disagree: an id, a name or a type on one side only. Mutation: `FIRST_VIEW`
//! moved to id 7 in `mask.vert`, or `Constant::Sharpen` given id 34, fails it.

use std::collections::BTreeMap;
use std::path::Path;

use foveate::plan::{Constant, ConstantKind};

/// (id → (name, GLSL type)) over every file of `shaders/`, each id declared alike everywhere.
fn glsl_constants() -> BTreeMap<u32, (String, String)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let mut found: BTreeMap<u32, (String, String)> = BTreeMap::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let text = std::fs::read_to_string(&path).unwrap();
        for line in text.lines() {
            let Some(rest) = line.trim().strip_prefix("layout(constant_id") else {
                continue;
            };
            // " = 5) const uint FIRST_VIEW = 0;"
            let (id, declaration) = rest.split_once(')').expect("layout(constant_id = N)");
            let id: u32 = id.trim_start_matches([' ', '=']).trim().parse().unwrap();
            let words: Vec<&str> = declaration.split_whitespace().collect();
            assert_eq!(words[0], "const", "{}: {line}", path.display());
            let declared = (words[2].to_string(), words[1].to_string());
            if let Some(before) = found.insert(id, declared.clone()) {
                assert_eq!(
                    before,
                    declared,
                    "{}: constant_id {id} declared differently in another shader",
                    path.display()
                );
            }
        }
    }
    found
}

#[test]
fn the_glsl_declares_each_constant_with_the_id_name_and_type_rust_declares() {
    let glsl = glsl_constants();
    let rust: BTreeMap<u32, (String, String)> = Constant::ALL
        .iter()
        .map(|c| {
            let (id, name, kind) = c.declaration();
            let ty = match kind {
                ConstantKind::Uint => "uint",
                ConstantKind::Float => "float",
                ConstantKind::Bool => "bool",
            };
            (id, (name.to_string(), ty.to_string()))
        })
        .collect();
    assert_eq!(rust.len(), Constant::ALL.len(), "two constants share an id");
    assert_eq!(
        glsl, rust,
        "GLSL (left) and plan::Constant (right) disagree"
    );
}

/// The compiled shaders' SpecId decorations are ids the table knows (the parser the renderer
/// uses to hand each stage its constants reads what glslc wrote).
#[test]
fn every_compiled_shader_declares_only_known_constants() {
    let known: Vec<u32> = Constant::ALL.iter().map(|c| c.id()).collect();
    let mut any = false;
    for shader in foveate::shaders::ALL
        .iter()
        .chain(foveate::shaders::COMPUTE)
    {
        for id in shader.spec_ids() {
            any = true;
            assert!(known.contains(&id), "{shader:?} declares constant_id {id}");
        }
    }
    assert!(any, "no SpecId found: the SPIR-V parser reads nothing");
    assert_eq!(
        foveate::shaders::MASK_VERT.spec_ids(),
        [Constant::ClipXyScale.id(), Constant::FirstView.id()]
    );
}
