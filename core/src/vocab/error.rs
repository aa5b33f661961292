/// A configuration the planner refuses, naming the field, the value given and the limit.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("invalid {field} = {value}: {limit}")]
pub struct ConfigError {
    pub field: &'static str,
    pub value: String,
    pub limit: String,
}

impl ConfigError {
    pub fn new(field: &'static str, value: impl ToString, limit: impl Into<String>) -> Self {
        Self {
            field,
            value: value.to_string(),
            limit: limit.into(),
        }
    }
}
