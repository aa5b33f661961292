/// A configuration the planner refuses, naming the field, the value given and the limit.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("invalid {field} = {value}: {limit}")]
pub struct ConfigError {
    /// The field (a `RenderConfig` field, or the CLI flag it comes from).
    pub field: &'static str,
    /// The value given.
    pub value: String,
    /// What it must be.
    pub limit: String,
}

impl ConfigError {
    /// The error for `field`, given `value`, which must be `limit`.
    pub fn new(field: &'static str, value: impl ToString, limit: impl Into<String>) -> Self {
        Self {
            field,
            value: value.to_string(),
            limit: limit.into(),
        }
    }
}
