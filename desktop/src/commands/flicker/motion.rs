//! The motions `foveate flicker` measures: per frame, the head pose and the gaze.

use foveate::foveation::{large_saccade_trace, simulated_trace, GazeSpace};
use foveate::scene::walking_pose;
use glam::{Mat4, Vec2};

use super::FlickerArgs;

/// Frame rate the motions are sampled at.
pub(super) const RATE_HZ: f64 = 90.0;

/// One motion: per frame, the head pose and the gaze.
pub(super) struct Motion {
    pub(super) kind: MotionKind,
    pub(super) frames: Vec<(Mat4, Vec2)>,
}

/// The motions `foveate flicker` measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub(super) enum MotionKind {
    Still,
    Saccades,
    LargeSaccades,
    Walking,
}

/// The motions asked for: head and gaze still; saccades with the head still (a simulated
/// trace); large saccades (15–30°) with the head still; a walk with the gaze at rest (`gaze`).
pub(super) fn motions(
    args: &FlickerArgs,
    gaze: Vec2,
    scene: &foveate::scene::Scene,
    space: GazeSpace,
) -> Vec<Motion> {
    let seconds = args.frames as f64 / RATE_HZ;
    let head = |gazes: Vec<Vec2>| gazes.into_iter().map(|g| (scene.head, g)).collect();
    args.motions
        .iter()
        .map(|kind| match kind {
            MotionKind::Still => Motion {
                kind: *kind,
                frames: vec![(scene.head, gaze); args.frames as usize],
            },
            MotionKind::Saccades => Motion {
                kind: *kind,
                frames: head(
                    simulated_trace(seconds, RATE_HZ, args.seed)
                        .iter()
                        .map(|s| s.left)
                        .collect(),
                ),
            },
            MotionKind::LargeSaccades => Motion {
                kind: *kind,
                frames: head(large_saccade_trace(
                    space,
                    seconds,
                    RATE_HZ,
                    (15.0, 30.0),
                    args.seed,
                )),
            },
            MotionKind::Walking => Motion {
                kind: *kind,
                frames: (0..args.frames)
                    .map(|i| {
                        let t = i as f32 / RATE_HZ as f32;
                        (walking_pose(scene.head, t), gaze)
                    })
                    .collect(),
            },
        })
        .collect()
}

impl MotionKind {
    /// How the table's rows name it.
    pub(super) fn name(self) -> &'static str {
        match self {
            MotionKind::Still => "still",
            MotionKind::Saccades => "saccades",
            MotionKind::LargeSaccades => "large saccades",
            MotionKind::Walking => "walking",
        }
    }
}

impl Motion {
    /// How the table's rows name it.
    pub(super) fn name(&self) -> &'static str {
        self.kind.name()
    }

    /// How the header line names it.
    pub(super) fn describe(&self, args: &FlickerArgs) -> String {
        match self.kind {
            MotionKind::Still => format!("still (head, gaze {})", self.resting_gaze()),
            MotionKind::Saccades => format!("saccades (seed {}, head still)", args.seed),
            MotionKind::LargeSaccades => {
                format!("large saccades (15–30°, seed {}, head still)", args.seed)
            }
            MotionKind::Walking => format!(
                "walking ({} m/s, turning {}°/s, gaze {})",
                foveate::scene::WALK_SPEED_M_S,
                foveate::scene::TURN_DEG_S,
                self.resting_gaze()
            ),
        }
    }

    /// Where the gaze rests (the still and walking motions keep their first frame's), as the
    /// header line says it.
    fn resting_gaze(&self) -> String {
        match self.frames.first().map(|&(_, gaze)| gaze) {
            Some(g) if g != Vec2::ZERO => format!("at ({}, {})", g.x, g.y),
            _ => "ahead".to_string(),
        }
    }
}
