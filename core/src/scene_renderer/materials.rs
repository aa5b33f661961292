//! Lit materials on the GPU: each texture kind (base colour, normal, occlusion-roughness-
//! metallic) one 2D array image with a layer per material and full mip chains, sampled
//! trilinearly (anisotropically where offered); the material factors and the lights. Only a
//! lit scene's renderer makes them.

use ash::vk;
use glam::Vec4;
use rayon::prelude::*;

use super::scene_buffers::upload;
use crate::foveation_layer::pipelines::LitBindings;
use crate::gpu::{
    pod_bytes, transition_image, Buffer, Gpu, GpuError, Image, ImageDesc, ImageState, ImageView,
    MemoryLocation, Sampler, VkResultExt,
};
use crate::plan::FramePlan;
use crate::scene::{textures::generate, MaterialTextures, Pattern, Scene, Surface, Texture};

/// One material as `Materials` in `shaders/lit.glsl` reads it (std430).
#[repr(C)]
#[derive(Clone, Copy)]
struct MaterialBlock {
    base_color: Vec4,
    params: Vec4,
}

/// `Lighting` in `shaders/lit.glsl` (std140).
#[repr(C)]
#[derive(Clone, Copy)]
struct LightingBlock {
    sun_color: Vec4,
    sky_color: Vec4,
    ground_color: Vec4,
    point_pos: [Vec4; 4],
    point_color: [Vec4; 4],
}

/// Which of a material's textures an array holds.
type PickTexture = fn(&MaterialTextures) -> &Texture;

pub(crate) struct MaterialSet {
    // Views before the images they view.
    pub views: [ImageView; 3],
    _images: [Image; 3],
    pub sampler: Sampler,
    pub materials: Buffer,
    pub lighting: Buffer,
}

impl MaterialSet {
    /// What the scene shaders bind of the set.
    pub fn bindings(&self) -> LitBindings<'_> {
        LitBindings {
            textures: &self.views,
            sampler: self.sampler.raw,
            materials: &self.materials,
            lighting: &self.lighting,
        }
    }

    /// Generates the scene's procedural textures (each pattern once, in parallel) and uploads
    /// them and its decoded ones with the material factors and the scene's lights.
    pub fn new(gpu: &Gpu, plan: &FramePlan, scene: &Scene) -> Result<Self, GpuError> {
        let mut patterns: Vec<Pattern> = scene
            .materials
            .iter()
            .filter_map(|m| match m.surface {
                Surface::Pattern(p) => Some(p),
                Surface::Images(_) => None,
            })
            .collect();
        patterns.sort_by_key(|p| *p as u32);
        patterns.dedup();
        let generated: Vec<MaterialTextures> = patterns.par_iter().map(|&p| generate(p)).collect();
        let textures: Vec<&MaterialTextures> = scene
            .materials
            .iter()
            .map(|m| match &m.surface {
                Surface::Pattern(pattern) => {
                    &generated[patterns
                        .iter()
                        .position(|p| p == pattern)
                        .expect("generated")]
                }
                Surface::Images(textures) => &**textures,
            })
            .collect();
        let kinds: [(&str, vk::Format, PickTexture); 3] = [
            ("base colour textures", vk::Format::R8G8B8A8_SRGB, |t| {
                &t.base
            }),
            ("normal textures", vk::Format::R8G8B8A8_UNORM, |t| &t.normal),
            (
                "occlusion-roughness-metallic textures",
                vk::Format::R8G8B8A8_UNORM,
                |t| &t.orm,
            ),
        ];
        let [base, normal, orm] = kinds.map(|(name, format, pick)| {
            let layers: Vec<&Texture> = textures.iter().map(|t| pick(t)).collect();
            upload_array(gpu, name, format, &layers)
        });
        let images = [base?, normal?, orm?];
        let view = |image: &Image| image.view(0, image.layers, true);
        let views = [view(&images[0])?, view(&images[1])?, view(&images[2])?];
        let anisotropy = plan.anisotropy;
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::LINEAR)
            .address_mode_u(vk::SamplerAddressMode::REPEAT)
            .address_mode_v(vk::SamplerAddressMode::REPEAT)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .anisotropy_enable(anisotropy.is_some())
            .max_anisotropy(anisotropy.unwrap_or(1.0))
            .max_lod(vk::LOD_CLAMP_NONE);
        // SAFETY: plain object creation, owned by the returned value.
        let sampler = Sampler::from_raw(
            &gpu.dev,
            unsafe { gpu.device().create_sampler(&info, None) }.vk("vkCreateSampler")?,
        );
        let blocks: Vec<MaterialBlock> = scene
            .materials
            .iter()
            .map(|m| MaterialBlock {
                base_color: m.base_color.extend(1.0),
                params: Vec4::new(
                    m.metallic,
                    m.roughness,
                    m.world_uv_scale,
                    m.alpha_cutoff.unwrap_or(0.0),
                ),
            })
            .collect();
        let materials = upload(
            gpu,
            "materials",
            pod_bytes(&blocks),
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        let mut lighting = Buffer::new(
            gpu,
            "lighting",
            std::mem::size_of::<LightingBlock>() as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        let mut block = LightingBlock {
            sun_color: Vec4::new(3.2, 3.0, 2.7, 0.0),
            sky_color: Vec4::new(0.45, 0.55, 0.7, 0.0),
            ground_color: Vec4::new(0.25, 0.22, 0.18, 0.0),
            point_pos: [Vec4::ZERO; 4],
            point_color: [Vec4::ZERO; 4],
        };
        for (i, l) in scene.lights.iter().enumerate() {
            block.point_pos[i] = l.position.extend(l.range);
            block.point_color[i] = l.color.extend(0.0);
        }
        lighting.write(&[block]);
        Ok(MaterialSet {
            views,
            _images: images,
            sampler,
            materials,
            lighting,
        })
    }
}

/// A sampled 2D array image, one layer per texture, every mip level uploaded.
fn upload_array(
    gpu: &Gpu,
    name: &str,
    format: vk::Format,
    layers: &[&Texture],
) -> Result<Image, GpuError> {
    let size = layers[0].size;
    let mip_levels = layers[0].levels.len() as u32;
    let image = Image::new(
        gpu,
        &ImageDesc {
            name,
            format,
            width: size,
            height: size,
            layers: layers.len() as u32,
            samples: 1,
            mip_levels,
            usage: vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
        },
    )?;
    let bytes: usize = layers
        .iter()
        .map(|t| t.levels.iter().map(Vec::len).sum::<usize>())
        .sum();
    let mut staging = Buffer::new(
        gpu,
        "texture staging",
        bytes as u64,
        vk::BufferUsageFlags::TRANSFER_SRC,
        MemoryLocation::CpuToGpu,
    )?;
    let mut regions = Vec::new();
    let mut offset = 0usize;
    let mapped = staging.mapped();
    for (layer, texture) in layers.iter().enumerate() {
        for (level, data) in texture.levels.iter().enumerate() {
            mapped[offset..offset + data.len()].copy_from_slice(data);
            let side = (size >> level).max(1);
            regions.push(
                vk::BufferImageCopy::default()
                    .buffer_offset(offset as u64)
                    .image_subresource(vk::ImageSubresourceLayers {
                        aspect_mask: vk::ImageAspectFlags::COLOR,
                        mip_level: level as u32,
                        base_array_layer: layer as u32,
                        layer_count: 1,
                    })
                    .image_extent(vk::Extent3D {
                        width: side,
                        height: side,
                        depth: 1,
                    }),
            );
            offset += data.len();
        }
    }
    let range = image.range(0, image.layers);
    let device = gpu.device();
    // SAFETY: recorded into one_shot's command buffer; the image outlives its wait.
    let transition = |cmd, src: ImageState, dst: ImageState| unsafe {
        transition_image(device, cmd, image.raw, range, src, dst)
    };
    let transfer_dst = (
        vk::PipelineStageFlags::TRANSFER,
        vk::AccessFlags::TRANSFER_WRITE,
        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
    );
    gpu.one_shot(|cmd| {
        let undefined = (
            vk::PipelineStageFlags::TOP_OF_PIPE,
            vk::AccessFlags::empty(),
            vk::ImageLayout::UNDEFINED,
        );
        transition(cmd, undefined, transfer_dst);
        // SAFETY: the image and staging buffer outlive one_shot's wait.
        unsafe {
            device.cmd_copy_buffer_to_image(
                cmd,
                staging.raw,
                image.raw,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &regions,
            )
        };
        let sampled = (
            vk::PipelineStageFlags::FRAGMENT_SHADER,
            vk::AccessFlags::SHADER_READ,
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        );
        transition(cmd, transfer_dst, sampled);
    })?;
    Ok(image)
}
