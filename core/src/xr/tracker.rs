//! The runtime's eye tracker, where the system has one (`XR_EXT_eye_gaze_interaction`): a pose
//! action bound to `/user/eyes_ext/input/gaze_ext/pose`, located each frame at the predicted
//! display time. Monado's simulated headsets have none, so this path has run here only as far
//! as detecting that; a failure in it falls back to the configured gaze (said once).

use glam::{Quat, Vec3};
use openxr as xr;

use super::error::{XrError, XrResultExt};

const PROFILE: &str = "/interaction_profiles/ext/eye_gaze_interaction";
const GAZE_POSE: &str = "/user/eyes_ext/input/gaze_ext/pose";

pub(super) struct EyeTracker {
    set: xr::ActionSet,
    space: xr::Space,
    _action: xr::Action<xr::Posef>,
}

impl EyeTracker {
    pub fn new(
        instance: &xr::Instance,
        session: &xr::Session<xr::Vulkan>,
    ) -> Result<Self, XrError> {
        let set = instance
            .create_action_set("foveate_gaze", "foveate gaze", 0)
            .xr("xrCreateActionSet")?;
        let action = set
            .create_action::<xr::Posef>("eye_gaze", "eye gaze", &[])
            .xr("xrCreateAction")?;
        let profile = instance.string_to_path(PROFILE).xr("xrStringToPath")?;
        let pose = instance.string_to_path(GAZE_POSE).xr("xrStringToPath")?;
        instance
            .suggest_interaction_profile_bindings(profile, &[xr::Binding::new(&action, pose)])
            .xr("xrSuggestInteractionProfileBindings")?;
        session
            .attach_action_sets(&[&set])
            .xr("xrAttachSessionActionSets")?;
        let space = action
            .create_space(session, xr::Path::NULL, xr::Posef::IDENTITY)
            .xr("xrCreateActionSpace")?;
        Ok(EyeTracker {
            set,
            space,
            _action: action,
        })
    }

    /// The gaze's direction in `base` at `time`; `None` while the tracker has no valid sample.
    pub fn direction(
        &self,
        session: &xr::Session<xr::Vulkan>,
        base: &xr::Space,
        time: xr::Time,
    ) -> Result<Option<Vec3>, XrError> {
        session
            .sync_actions(&[xr::ActiveActionSet::new(&self.set)])
            .xr("xrSyncActions")?;
        let location = self.space.locate(base, time).xr("xrLocateSpace")?;
        let valid = location.location_flags.contains(
            xr::SpaceLocationFlags::ORIENTATION_VALID | xr::SpaceLocationFlags::ORIENTATION_TRACKED,
        );
        let o = location.pose.orientation;
        Ok(valid.then(|| Quat::from_xyzw(o.x, o.y, o.z, o.w).normalize() * Vec3::NEG_Z))
    }
}
