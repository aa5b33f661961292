//! Recording the coverage probe: one full-view triangle under the pass's masks, counted per view
//! (`foveate pixels` measures with it).

use super::recorder::{Recorder, Rect};
use crate::plan::PassPlan;

pub(super) fn record_probe(pass: &PassPlan, area: Rect, rec: &mut dyn Recorder) {
    rec.set_viewport(area, pass.guard_band);
    rec.draw(3);
}
