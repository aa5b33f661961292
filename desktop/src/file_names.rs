//! File names made from configuration names, for the pictures commands write into a folder.

/// A configuration's name as a file name: lower-case letters, digits and dots, runs of anything
/// else one dash (`foveated 0.35, MSAA 4` → `foveated-0.35-msaa-4`).
pub fn slug(name: &str) -> String {
    let mut out = String::new();
    for c in name.chars() {
        if c.is_ascii_alphanumeric() || c == '.' {
            out.push(c.to_ascii_lowercase());
        } else if !out.ends_with('-') {
            out.push('-');
        }
    }
    out.trim_matches('-').to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slugs_are_file_names() {
        assert_eq!(
            slug("foveated 0.35, sharpen 0.5, MSAA 4"),
            "foveated-0.35-sharpen-0.5-msaa-4"
        );
    }
}
