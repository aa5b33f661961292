//! Recording the stereo scene step: the scene's geometry, submitted as the pass's strategy
//! says (Wilson 2015: multiview, one eye, instanced, each object twice).

use super::recorder::{Recorder, Rect};
use crate::mffr::FAR_VIEW_INDEX;
use crate::plan::{FramePlan, PassPlan, Submission};
use crate::scene::Draw;
use crate::view::Eye;

/// The scene step: geometry bound, then the draws.
pub(super) fn record_scene(
    plan: &FramePlan,
    pass: &PassPlan,
    area: Rect,
    draws: &[Draw],
    rec: &mut dyn Recorder,
) {
    rec.bind_geometry();
    submit(plan, pass, area, draws, rec);
}

/// The scene's draws as the pass's submission says: once for multiview, instanced (instance
/// count doubled: instance 2k is object k's left eye, 2k+1 its right), a single eye or the far
/// view; or every object twice with the view switched between (per-object).
fn submit(plan: &FramePlan, pass: &PassPlan, area: Rect, draws: &[Draw], rec: &mut dyn Recorder) {
    let view = |rec: &mut dyn Recorder, area, view: u32| {
        rec.set_viewport(area, pass.guard_band);
        rec.push_vertex(view);
    };
    match pass.submission {
        Submission::Multiview | Submission::Instanced => {
            view(rec, area, 0);
            let k = if pass.submission == Submission::Instanced {
                2
            } else {
                1
            };
            for d in draws {
                rec.draw_indexed(d.mesh, d.instance_count * k, d.first_instance * k);
            }
        }
        Submission::SingleEye(_) | Submission::FarView => {
            let index = match pass.submission {
                Submission::SingleEye(eye) => eye.index() as u32,
                _ => FAR_VIEW_INDEX,
            };
            view(rec, area, index);
            for d in draws {
                rec.draw_indexed(d.mesh, d.instance_count, d.first_instance);
            }
        }
        Submission::PerObject => {
            let width = plan.eye_resolution.width;
            for d in draws {
                for i in 0..d.instance_count {
                    for eye in Eye::BOTH {
                        let half = Rect {
                            x: eye.index() as u32 * width,
                            width,
                            ..area
                        };
                        view(rec, half, eye.index() as u32);
                        rec.draw_indexed(d.mesh, 1, d.first_instance + i);
                    }
                }
            }
        }
    }
}
