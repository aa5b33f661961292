//! Command-line names for unit enums: `name`, `Display` and a `FromStr` whose error names the
//! field and every accepted value.

/// `named_enum!(Type, "field", [Type::A => "a", Type::B => "b"])`.
macro_rules! named_enum {
    ($t:ty, $field:literal, [$($v:path => $name:literal),+ $(,)?]) => {
        impl $t {
            /// Its name on the command line and in the printout.
            pub fn name(self) -> &'static str {
                match self {
                    $($v => $name,)+
                }
            }
        }
        impl std::fmt::Display for $t {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.name())
            }
        }
        impl std::str::FromStr for $t {
            type Err = $crate::vocab::ConfigError;
            fn from_str(s: &str) -> Result<Self, Self::Err> {
                $(if s == $name {
                    return Ok($v);
                })+
                Err($crate::vocab::ConfigError::new(
                    $field,
                    s,
                    format!("one of {}", [$($name),+].join(", ")),
                ))
            }
        }
    };
}
pub(crate) use named_enum;
