//! Each compared configuration's map of what the lens shows, region by region (fovea, band,
//! periphery) and eccentricity from the gaze, kept while the gaze rests.

use foveate::foveation::FoveationGeometry;
use foveate::metrics::{EyePixels, PixelsKey};
use foveate::plan::FramePlan;
use glam::Vec2;

/// The maps of a run's configurations at one gaze. A map depends on the screen, the lens and the
/// fovea's placement, not on how the periphery is rendered (its density, samples or
/// accumulation), so configurations with the same fovea share one: at a headset's panel a map
/// costs seconds of CPU, and a saccade trace asks for one at nearly every frame.
#[derive(Default)]
pub struct RegionMaps {
    gaze: Option<Vec2>,
    /// The maps made at `gaze`, each with what it was made for.
    made: Vec<(PixelsKey, [EyePixels; 2])>,
    /// Per configuration, the index of its map in `made`.
    of_config: Vec<usize>,
}

impl RegionMaps {
    /// Makes every configuration's map (`plans`, in order) for the eyes looking at `gaze`,
    /// unless they are at it already. Returns how many maps it made. A frame without a fovea
    /// has its regions where the first foveated plan on its screen puts them
    /// ([`regions_of`]), so its error there stands beside theirs.
    pub fn look_at(&mut self, gaze: Vec2, plans: &[FramePlan]) -> usize {
        if self.gaze == Some(gaze) && self.of_config.len() == plans.len() {
            return 0;
        }
        self.gaze = Some(gaze);
        self.made.clear();
        self.of_config.clear();
        for plan in plans {
            let foveation = regions_of(plan, plans);
            let key = PixelsKey::placed(plan, foveation);
            let index = match self.made.iter().position(|(k, _)| *k == key) {
                Some(index) => index,
                None => {
                    let map = EyePixels::both(plan, gaze, foveation);
                    self.made.push((key, map));
                    self.made.len() - 1
                }
            };
            self.of_config.push(index);
        }
        self.made.len()
    }

    /// Configuration `config`'s map (of the plans last given to [`RegionMaps::look_at`]).
    pub fn of(&self, config: usize) -> &[EyePixels; 2] {
        &self.made[self.of_config[config]].1
    }
}

/// The foveation that places `plan`'s regions: its own, or for a frame without one the first
/// of `plans` on the same screen and output that has one (none if no plan has).
pub fn regions_of<'a>(
    plan: &'a FramePlan,
    plans: &'a [FramePlan],
) -> Option<&'a FoveationGeometry> {
    plan.foveation.as_ref().or_else(|| {
        (plans.iter())
            .filter(|p| p.eye_resolution == plan.eye_resolution)
            .filter(|p| p.lens.is_some() == plan.lens.is_some())
            .find_map(|p| p.foveation.as_ref())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use foveate::foveation::FoveationConfig;
    use foveate::plan::{DeviceCaps, RenderConfig, Resolution};

    fn plan(foveation: Option<FoveationConfig>) -> FramePlan {
        let config = RenderConfig {
            resolution: Some(Resolution::square(48)),
            foveation,
            ..RenderConfig::default()
        };
        foveate::plan(
            &foveate::scene::default_scene(),
            &config,
            &DeviceCaps::generic(),
        )
        .unwrap()
    }

    /// Rows that differ only in the periphery share a map; another fovea gets its own; a
    /// frame without a fovea has the first foveated row's regions (so its error in the fovea
    /// stands beside theirs), or none when no row has a fovea; each is the map made directly.
    /// Mutations: a key without the fovea's ratio shares the 0.35 and 0.5 rows' map; a stereo
    /// frame placed by its own (absent) foveation has no fovea region; both fail.
    #[test]
    fn rows_with_the_same_fovea_share_one_map() {
        let fovea = |ratio, periphery_density| {
            Some(FoveationConfig {
                ratio,
                periphery_density,
                ..FoveationConfig::single_frame()
            })
        };
        let plans = [
            plan(None),
            plan(fovea(0.35, None)),
            plan(fovea(0.35, Some(0.5))),
            plan(fovea(0.5, None)),
        ];
        let gaze = Vec2::new(0.3, -0.2);
        let mut maps = RegionMaps::default();
        assert_eq!(maps.look_at(gaze, &plans), 2);
        assert_eq!(maps.look_at(gaze, &plans), 0, "the gaze rests");
        assert!(std::ptr::eq(maps.of(1), maps.of(2)));
        assert!(
            std::ptr::eq(maps.of(0), maps.of(1)),
            "stereo at 0.35's regions"
        );
        assert!(!std::ptr::eq(maps.of(1), maps.of(3)));
        let in_fovea = |map: &[EyePixels; 2]| {
            (map.iter().flat_map(|m| m.pixels.iter().flatten()))
                .any(|p| p.region == foveate::metrics::Region::Fovea)
        };
        assert!(in_fovea(maps.of(0)), "the stereo frame has a fovea region");
        for (i, plan) in plans.iter().enumerate() {
            let direct = EyePixels::both(plan, gaze, regions_of(plan, &plans));
            for (shared, direct) in maps.of(i).iter().zip(&direct) {
                assert!(shared == direct, "row {i}");
            }
        }
        assert_eq!(maps.look_at(Vec2::ZERO, &plans), 2, "the gaze moved");
        let alone = [plan(None)];
        assert!(regions_of(&alone[0], &alone).is_none());
        assert_eq!(maps.look_at(gaze, &alone), 1);
        assert!(!in_fovea(maps.of(0)), "no fovea anywhere: all periphery");
    }
}
