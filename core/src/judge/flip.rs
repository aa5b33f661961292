//! FLIP and the eccentricity-aware FLIP as compute passes on the device: both images to YCxCz
//! and a tent-filtered pyramid of them, then per ppd level the separable filters (along rows,
//! along columns; on a coarse level, the fields resampled to the judged pixels' columns) and the
//! level's error at every judged pixel, summed into the eccentricity-aware map with the weights
//! `metrics::flip` interpolates its levels with. One submission per judgement.

use ash::vk;
use rayon::prelude::*;

use super::filters::{
    colour_taps, feature_taps, max_colour_difference, pyramid_blur, pyramid_level,
};
use super::geometry::{
    add_to, level_region, merge, origin, pyramid_depth, pyramid_levels, LevelRegions, PyramidLevel,
    Region,
};
use super::images::JudgedImage;
use super::reduce::Reduction;
use super::vulkan::{compute_pipeline, SharedSet, FLIP_SHADERS};
use crate::gpu::{Buffer, Gpu, GpuError, MemoryLocation, Pipeline};
use crate::metrics::acuity::LEVELS;
use crate::metrics::{Acuity, EyeFlipErrors, EyePixels, FlipMaps, RgbaImage, HISTOGRAM_BINS};
use crate::plan::ConfigError;
use crate::render::OutputTexels;

/// The storage buffers the passes share, by binding (see `shaders/flip_common.glsl`).
const BINDINGS: u32 = 10;

/// Histograms per judgement: the plain FLIP, then the eccentricity-aware FLIP per region.
const HISTOGRAMS: usize = 1 + crate::metrics::Region::ALL.len();

/// Pixels per workgroup side (`local_size_x`, `local_size_y`).
const GROUP: u32 = 8;

/// The passes' push constants (`Params` in `shaders/flip_common.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Default)]
pub(super) struct Params {
    full: [i32; 2],
    size: [i32; 2],
    src: i32,
    dst: i32,
    spatial_radius: i32,
    feature_radius: i32,
    spatial_taps: i32,
    feature_taps: i32,
    level: i32,
    scale: f32,
    cmax: f32,
    pad: i32,
    origin: [i32; 2],
    rows_origin: [i32; 2],
    rows_size: [i32; 2],
    src_pad: i32,
    bins: i32,
    /// std430 aligns the ivec4s that follow to 16 bytes.
    _align: [i32; 2],
    reference: [i32; 4],
    test: [i32; 4],
}

/// One ppd level to judge: its filters' taps in the taps buffer, at which pyramid level.
struct LevelWork {
    level: u32,
    pyramid: usize,
    colour: (i32, i32),
    feature: (i32, i32),
    /// The judged pixels that take a share of this level.
    region: Region,
}

/// FLIP judged on the GPU for images of one size: the compute pipelines and the buffers, made
/// once and reused by every judgement.
pub struct FlipJudge {
    pub(super) gpu: Gpu,
    pub(super) width: u32,
    pub(super) height: u32,
    /// How many pyramid levels the image allows (the judged resolution included).
    depth: u32,
    /// This judgement's pyramid.
    pyramid: Vec<PyramidLevel>,
    // Declared before the layouts and buffers they use, so they are dropped first.
    pub(super) pipelines: [Pipeline; 8],
    shared: SharedSet,
    inputs: Buffer,
    /// Two frames as copied, when a judgement reads them in place (see `judge::outputs`); a
    /// token buffer until then.
    pub(super) frames: Buffer,
    /// The capture `frames` holds (`GpuFlip::record_capture`), until something else is
    /// copied there; and how many captures there were.
    pub(super) capture: Option<u64>,
    pub(super) captures: u64,
    positions: Buffer,
    maps: Buffer,
    /// The labels up, the histograms and the maps back.
    reduction: Reduction,
    /// The pyramid, the row sums, the filtered fields and the taps, sized by each judgement.
    work: [Option<Buffer>; 4],
    cmax: f32,
}

impl FlipJudge {
    /// A judge of `width` × `height` images on `gpu`.
    pub fn new(gpu: &Gpu, width: u32, height: u32) -> Result<Self, GpuError> {
        if width == 0 || height == 0 || width > 16384 || height > 16384 {
            let size = format!("{width}x{height}");
            return Err(ConfigError::new("judged image", size, "1 to 16384 pixels a side").into());
        }
        let pixels = width as u64 * height as u64;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let buffer =
            |name: &str, size: u64, location| Buffer::new(gpu, name, size, storage, location);
        let inputs = buffer("flip inputs", 2 * 4 * pixels, MemoryLocation::CpuToGpu)?;
        let positions = buffer("flip level positions", 4 * pixels, MemoryLocation::CpuToGpu)?;
        let maps = Buffer::new(
            gpu,
            "flip maps",
            8 * pixels,
            storage | vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::GpuOnly,
        )?;
        let reduction = Reduction::new(gpu, pixels, HISTOGRAMS)?;
        let frames = super::outputs::frames_buffer(gpu, 16)?;
        let shared = SharedSet::new(gpu, BINDINGS, std::mem::size_of::<Params>() as u32)?;
        let mut pipelines = Vec::with_capacity(FLIP_SHADERS.len());
        for shader in FLIP_SHADERS {
            pipelines.push(compute_pipeline(gpu, &shared.layout, shader)?);
        }
        let judge = FlipJudge {
            gpu: gpu.clone(),
            width,
            height,
            depth: pyramid_depth(width, height),
            pyramid: Vec::new(),
            pipelines: pipelines.try_into().unwrap_or_else(|_| unreachable!()),
            shared,
            inputs,
            frames,
            capture: None,
            captures: 0,
            positions,
            maps,
            reduction,
            work: [None, None, None, None],
            cmax: max_colour_difference(),
        };
        Ok(judge)
    }

    /// The judged images' size.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// Both FLIP maps of `test` against `reference`, as `metrics::flip`'s `eccentric_flip_map`
    /// (feature `flip`) defines them, computed on the GPU: the display's `ppd` at the gaze,
    /// the eye's `acuity`, and each pixel's angle from the gaze (`None`: not judged, `NaN` in
    /// both maps). The ppd levels whose filters are wide are filtered on a coarser pyramid
    /// level and sampled back with Catmull-Rom (the approximation the judge's tests bound).
    pub fn flip_maps(
        &mut self,
        reference: &RgbaImage,
        test: &RgbaImage,
        ppd: f64,
        acuity: Acuity,
        eccentricity: &(dyn Fn(u32, u32) -> Option<f64> + Sync),
    ) -> Result<FlipMaps, GpuError> {
        self.reduction.want_maps(&self.gpu)?;
        let source = Source::Images(reference, test);
        self.run(source, ppd, acuity, eccentricity, Bring::Maps)?;
        let (plain, eccentric) = self.reduction.maps().unwrap_or_default();
        Ok(FlipMaps { plain, eccentric })
    }

    /// One eye's figures, as [`crate::metrics::FlipMapper::flip_errors`] defines them: the
    /// maps as [`FlipJudge::flip_maps`] computes them for the pixels `pixels` shows, reduced
    /// to histograms on the GPU; only those come back, and the eccentricity-aware map if
    /// `keep_map`.
    pub fn flip_errors(
        &mut self,
        reference: &RgbaImage,
        test: &RgbaImage,
        pixels: &EyePixels,
        acuity: Acuity,
        keep_map: bool,
    ) -> Result<EyeFlipErrors, GpuError> {
        let source = Source::Images(reference, test);
        self.eye_errors(source, pixels, acuity, keep_map)
    }

    /// One eye's figures of `source`'s images over the pixels `pixels` shows: histograms back,
    /// and the eccentricity-aware map if `keep_map`.
    pub(super) fn eye_errors(
        &mut self,
        source: Source,
        pixels: &EyePixels,
        acuity: Acuity,
        keep_map: bool,
    ) -> Result<EyeFlipErrors, GpuError> {
        if (pixels.width, pixels.height) != (self.width, self.height) {
            let size = format!("{}x{}", pixels.width, pixels.height);
            let limit = format!("the judge's size, {}x{}", self.width, self.height);
            return Err(ConfigError::new("judged pixels", size, limit).into());
        }
        self.reduction.upload_labels(&[pixels]);
        let bring = if keep_map {
            self.reduction.want_maps(&self.gpu)?;
            Bring::HistogramsAndMaps
        } else {
            Bring::Histograms
        };
        let eccentricity = |x: u32, y: u32| pixels.at(x, y).map(|d| d.eccentricity_deg);
        self.run(source, pixels.ppd, acuity, &eccentricity, bring)?;
        let mut histograms = self.reduction.histograms().into_iter();
        let mut next = || histograms.next().unwrap_or_default();
        let plain = next();
        Ok(EyeFlipErrors {
            plain,
            regions: [next(), next(), next()],
            map: if keep_map {
                self.reduction.maps().map(|(_, eccentric)| eccentric)
            } else {
                None
            },
        })
    }

    /// One judgement on the GPU, bringing back what `bring` says.
    fn run(
        &mut self,
        source: Source,
        ppd: f64,
        acuity: Acuity,
        eccentricity: &(dyn Fn(u32, u32) -> Option<f64> + Sync),
        bring: Bring,
    ) -> Result<(), GpuError> {
        if !(ppd.is_finite() && ppd > 0.0 && ppd <= 1000.0) {
            return Err(ConfigError::new("ppd", ppd, "0 < ppd ≤ 1000").into());
        }
        acuity.check()?;
        let mut params = Params {
            full: [self.width as i32, self.height as i32],
            cmax: self.cmax,
            bins: HISTOGRAM_BINS as i32,
            ..Params::default()
        };
        let gather = match source {
            Source::Images(reference, test) => {
                self.check_inputs(reference, test)?;
                self.upload_images(reference, test);
                None
            }
            Source::Outputs {
                images,
                texels,
                eye,
            } => {
                let params_of = self.outputs_to_gather(texels, eye)?;
                (params.reference, params.test) = (params_of[0], params_of[1]);
                Some((images, texels))
            }
        };
        let used = self.upload_positions(acuity, eccentricity);
        let work = self.filters(ppd as f32, &used)?;
        self.gpu.one_shot(|cmd| {
            if let Some((images, texels)) = gather {
                self.record_gather(cmd, params, images, texels);
            }
            self.record(cmd, params, &work, bring)
        })
    }

    fn check_inputs(&self, reference: &RgbaImage, test: &RgbaImage) -> Result<(), GpuError> {
        for (name, image) in [("reference image", reference), ("test image", test)] {
            if (image.width, image.height) != (self.width, self.height) {
                let size = format!("{}x{}", image.width, image.height);
                let limit = format!("the judge's size, {}x{}", self.width, self.height);
                return Err(ConfigError::new(name, size, limit).into());
            }
        }
        Ok(())
    }

    /// Writes both images.
    fn upload_images(&mut self, reference: &RgbaImage, test: &RgbaImage) {
        let bytes = reference.data.len();
        let inputs = self.inputs.mapped();
        inputs[..bytes].copy_from_slice(&reference.data);
        inputs[bytes..2 * bytes].copy_from_slice(&test.data);
    }

    /// Writes each pixel's level position; returns which ppd levels any pixel takes a share
    /// of.
    fn upload_positions(
        &mut self,
        acuity: Acuity,
        eccentricity: &(dyn Fn(u32, u32) -> Option<f64> + Sync),
    ) -> LevelRegions {
        let width = self.width as usize;
        let positions: Vec<f32> = (0..self.height)
            .into_par_iter()
            .flat_map_iter(|y| {
                (0..width as u32).map(move |x| {
                    eccentricity(x, y).map_or(-1.0, |e| acuity.level_position(e) as f32)
                })
            })
            .collect();
        let regions = positions
            .par_chunks(width)
            .enumerate()
            .fold(LevelRegions::default, |mut regions, (y, row)| {
                for (x, &t) in row.iter().enumerate().filter(|(_, t)| **t >= 0.0) {
                    let (x, y) = (x as u32, y as u32);
                    // Level 0 for the plain map; the two levels around t (one when t is a
                    // level) for the eccentricity-aware one.
                    add_to(&mut regions, 0, x, y);
                    add_to(&mut regions, t.floor() as usize, x, y);
                    add_to(
                        &mut regions,
                        (t.ceil() as usize).min(LEVELS.len() - 1),
                        x,
                        y,
                    );
                }
                regions
            })
            .reduce(LevelRegions::default, merge);
        self.positions.write(&positions);
        // Level 0 always runs: it writes both maps, NaN where nothing is judged.
        let mut regions = regions;
        regions[0].get_or_insert(Region::point(0, 0));
        regions
    }

    /// The taps of every level to judge, in one buffer; where each level filters; the pyramid
    /// those levels need, each level extending past the image by its widest filter's reach.
    fn filters(&mut self, ppd: f32, used: &LevelRegions) -> Result<Vec<LevelWork>, GpuError> {
        let mut taps: Vec<[f32; 4]> = Vec::new();
        let mut work = Vec::new();
        let mut pads = vec![0u32; self.depth as usize];
        for (level, k) in LEVELS.iter().enumerate() {
            let Some(region) = used[level] else { continue };
            let pyramid = pyramid_level(ppd * *k as f32, self.depth - 1) as usize;
            let level_ppd = ppd * *k as f32 / 2f32.powi(pyramid as i32);
            let mut add = |t: Vec<[f32; 4]>| {
                let entry = (taps.len() as i32, (t.len() as i32 - 1) / 2);
                taps.extend(t);
                entry
            };
            let blur = pyramid_blur(2f32.powi(pyramid as i32));
            let colour = add(colour_taps(level_ppd, blur));
            let feature = add(feature_taps(level_ppd, blur));
            if pyramid > 0 {
                let reach = colour.1.max(feature.1) as u32 + 1;
                pads[pyramid] = pads[pyramid].max(reach);
            }
            work.push(LevelWork {
                level: level as u32,
                pyramid,
                colour,
                feature,
                region,
            });
        }
        let deepest = work.iter().map(|w| w.pyramid).max().unwrap_or(0);
        // Each level is made from the one before it, whose padding must cover what its tents
        // read: two source texels per padding texel, and one more either side.
        for p in (2..=deepest).rev() {
            pads[p - 1] = pads[p - 1].max(2 * pads[p] + 2);
        }
        self.pyramid = pyramid_levels(self.width, self.height, &pads[..=deepest]);
        let texels = |l: &PyramidLevel| l.width as u64 * l.height as u64;
        let largest = work.iter().map(|w| texels(&self.pyramid[w.pyramid])).max();
        // Only the coarse levels write their fields (the judged resolution judges in place).
        let coarse = work.iter().filter(|w| w.pyramid > 0);
        let largest_coarse = coarse.map(|w| texels(&self.pyramid[w.pyramid])).max();
        let rows = work.iter().filter(|w| w.pyramid > 0).map(|w| {
            let (columns, rows) = self.resampled_rows(w).extent();
            columns as u64 * rows as u64
        });
        let sizes = [
            16 * 2 * self.pyramid.iter().map(texels).sum::<u64>(),
            64 * largest.into_iter().chain(rows).max().unwrap_or(0),
            64 * largest_coarse.unwrap_or(1),
            16 * taps.len() as u64,
        ];
        self.ensure_buffers(sizes)?;
        if let Some(buffer) = &mut self.work[3] {
            buffer.write(&taps);
        }
        self.bind_buffers();
        Ok(work)
    }

    /// The fields' texels a coarse level's judged pixels sample (Catmull-Rom: the 4×4 texels
    /// around each).
    fn sampled_fields(&self, w: &LevelWork) -> Region {
        level_region(
            w.region,
            &self.pyramid[w.pyramid],
            2f32.powi(w.pyramid as i32),
        )
    }

    /// A coarse level's fields resampled along rows: the judged pixels' columns, by the texel
    /// rows they sample.
    fn resampled_rows(&self, w: &LevelWork) -> Region {
        let fields = self.sampled_fields(w);
        Region {
            min: [w.region.min[0], fields.min[1]],
            max: [w.region.max[0], fields.max[1]],
        }
    }

    /// Makes each work buffer anew where this judgement needs it larger.
    fn ensure_buffers(&mut self, sizes: [u64; 4]) -> Result<(), GpuError> {
        const NAMES: [&str; 4] = ["flip pyramid", "flip row sums", "flip fields", "flip taps"];
        for (i, size) in sizes.into_iter().enumerate() {
            if self.work[i].as_ref().is_none_or(|b| b.size < size) {
                let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
                let location = if i == 3 {
                    MemoryLocation::CpuToGpu
                } else {
                    MemoryLocation::GpuOnly
                };
                self.work[i] = None;
                self.work[i] = Some(Buffer::new(&self.gpu, NAMES[i], size, usage, location)?);
            }
        }
        Ok(())
    }

    /// Points the descriptor set at the buffers (the work buffers may be new).
    fn bind_buffers(&self) {
        let [Some(pyramid), Some(sums), Some(fields), Some(taps)] = &self.work else {
            return;
        };
        let buffers = [
            &self.inputs,
            pyramid,
            sums,
            fields,
            taps,
            &self.positions,
            &self.maps,
            &self.reduction.labels,
            &self.reduction.counts,
            &self.frames,
        ];
        self.shared.bind(&self.gpu, &buffers);
    }

    /// Records a judgement: YCxCz, the pyramid, then per ppd level the filters and the errors;
    /// then what `bring` says comes back.
    fn record(&self, cmd: vk::CommandBuffer, base: Params, work: &[LevelWork], bring: Bring) {
        let full = (self.width, self.height);
        let device = self.gpu.device();
        let histograms = bring != Bring::Maps;
        if histograms {
            self.reduction.record_clear(device, cmd);
        }
        self.dispatch(cmd, 0, base, full);
        // The pyramid, each level from the one before it.
        for pair in self.pyramid.windows(2) {
            let (from, to) = (pair[0], pair[1]);
            let params = Params {
                full: [from.width as i32, from.height as i32],
                src: from.offset as i32,
                src_pad: from.pad as i32,
                size: [to.width as i32, to.height as i32],
                dst: to.offset as i32,
                pad: to.pad as i32,
                ..base
            };
            self.dispatch(cmd, 1, params, (to.width, to.height));
        }
        for w in work {
            let at = self.pyramid[w.pyramid];
            let params = Params {
                size: [at.width as i32, at.height as i32],
                src: at.offset as i32,
                spatial_taps: w.colour.0,
                spatial_radius: w.colour.1,
                feature_taps: w.feature.0,
                feature_radius: w.feature.1,
                level: w.level as i32,
                scale: 2f32.powi(w.pyramid as i32),
                pad: at.pad as i32,
                ..base
            };
            self.record_level(cmd, params, w);
        }
        if histograms {
            self.dispatch(cmd, 6, base, full);
        }
        let maps = (bring != Bring::Histograms).then_some(&self.maps);
        self.reduction
            .record_read_back(device, cmd, histograms, maps);
    }

    /// One ppd level: the filters along rows and along columns, and each judged pixel's share
    /// of the level's error. At the judged resolution the column pass judges the pixels itself;
    /// on a coarse level it writes the fields, resampled along rows and then judged.
    fn record_level(&self, cmd: vk::CommandBuffer, params: Params, w: &LevelWork) {
        // Level 0 covers every pixel: it writes the maps, NaN where nothing is judged.
        let pixels = if w.level == 0 {
            Region {
                min: [0, 0],
                max: [self.width, self.height],
            }
        } else {
            w.region
        };
        let columns = if w.pyramid == 0 {
            pixels
        } else {
            self.sampled_fields(w)
        };
        // The row sums the column pass reads.
        let reach = w.colour.1.max(w.feature.1) as u32;
        let height = self.pyramid[w.pyramid].height;
        let sums = Region {
            min: [columns.min[0], columns.min[1].saturating_sub(reach)],
            max: [columns.max[0], (columns.max[1] + reach).min(height)],
        };
        let over = |region: &Region| Params {
            origin: origin(region),
            ..params
        };
        self.dispatch(cmd, 2, over(&sums), sums.extent());
        self.dispatch(cmd, 3, over(&columns), columns.extent());
        if w.pyramid == 0 {
            return;
        }
        let rows = self.resampled_rows(w);
        let params = Params {
            rows_origin: origin(&rows),
            rows_size: [rows.extent().0 as i32, rows.extent().1 as i32],
            ..params
        };
        self.dispatch(cmd, 5, params, rows.extent());
        let origin = origin(&pixels);
        self.dispatch(cmd, 4, Params { origin, ..params }, pixels.extent());
    }

    /// One pass over `extent` pixels, after everything recorded before it.
    pub(super) fn dispatch(
        &self,
        cmd: vk::CommandBuffer,
        pass: usize,
        params: Params,
        extent: (u32, u32),
    ) {
        let groups = [extent.0.div_ceil(GROUP), extent.1.div_ceil(GROUP), 1];
        let push = crate::gpu::pod_bytes(std::slice::from_ref(&params));
        (self.shared).dispatch(self.gpu.device(), cmd, &self.pipelines[pass], push, groups);
    }
}

/// Where a judgement's two images come from.
pub(super) enum Source<'a> {
    /// Images on the host, uploaded.
    Images(&'a RgbaImage, &'a RgbaImage),
    /// Eye `eye` of two frames on the device, gathered from the frames buffer: copied there
    /// first (`images`), or captured there before (`None`) (`judge::outputs`).
    Outputs {
        images: Option<[JudgedImage<'a>; 2]>,
        texels: [OutputTexels; 2],
        eye: usize,
    },
}

/// What a judgement brings back to the host.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Bring {
    /// Both maps (the oracle tests' comparison).
    Maps,
    /// The histograms only.
    Histograms,
    /// The histograms and the maps.
    HistogramsAndMaps,
}
