//! The derivation rules: from what passes declare about an attachment (its [`Access`]) and
//! who reads it afterwards, to Vulkan load/store ops and transient usage.

use std::fmt;

/// What a pass declares about an attachment's contents when it starts using it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    /// Starts from a cleared value; earlier contents are irrelevant.
    Clear,
    /// Every pixel is overwritten (e.g. an MSAA resolve target); earlier contents irrelevant.
    Overwrite,
    /// Continues from the contents an earlier pass (or frame) left.
    Keep,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LoadOp {
    Clear,
    Load,
    DontCare,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StoreOp {
    Store,
    DontCare,
}

impl LoadOp {
    pub fn from_access(access: Access) -> Self {
        match access {
            Access::Clear => LoadOp::Clear,
            Access::Overwrite => LoadOp::DontCare,
            Access::Keep => LoadOp::Load,
        }
    }
}

impl StoreOp {
    /// Contents are stored only when someone reads them after the pass.
    pub fn from_read_later(read_later: bool) -> Self {
        if read_later {
            StoreOp::Store
        } else {
            StoreOp::DontCare
        }
    }
}

/// An attachment can live only on tile (transient, lazily allocated where the device offers
/// it) when no pass ever loads or stores it.
pub fn is_transient(loads: &[LoadOp], stores: &[StoreOp]) -> bool {
    !loads.contains(&LoadOp::Load) && !stores.contains(&StoreOp::Store)
}

impl fmt::Display for LoadOp {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            LoadOp::Clear => "CLEAR",
            LoadOp::Load => "LOAD",
            LoadOp::DontCare => "DONT_CARE",
        })
    }
}

impl fmt::Display for StoreOp {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            StoreOp::Store => "STORE",
            StoreOp::DontCare => "DONT_CARE",
        })
    }
}
