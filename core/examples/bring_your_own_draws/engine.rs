//! A minimal engine of its own: its own vertex layout (a position and a normal), its own
//! shaders, buffers, descriptor sets and pipelines, made with raw Vulkan on the device foveate
//! opened. It draws its world into the views a `FoveationLayer` hands it, with the stencil
//! test each pass asks for, culling its objects against each pass's superfrustum. Shared by
//! the `bring_your_own_draws` example and the tests that hold its frames to foveate's own
//! renderer's (`core/tests/engine_draws.rs`).

use std::path::Path;

use foveate::ash::{self, vk};
use foveate::cull::Sphere;
use foveate::glam::{Mat4, Vec3, Vec4};
use foveate::gpu::Gpu;
use foveate::render::{DrawContext, DrawPass, View};
use foveate::scene::Shading;

/// The engine's shaders (compiled from `engine.vert` and `engine.frag` beside this file).
const VERTEX_SHADER: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/byod_engine.vert.spv"));
const FRAGMENT_SHADER: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/byod_engine.frag.spv"));

/// The most views a frame has (two eyes, two fovea insets).
pub const MAX_VIEWS: usize = 4;

/// The engine's vertex: 24 bytes.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct EngineVertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
}

/// `Frame` in the engine's shaders (std140).
#[repr(C)]
#[derive(Clone, Copy)]
struct FrameBlock {
    clip_from_world: [Mat4; MAX_VIEWS],
    light_dir: Vec4,
    view_tint: [Vec4; MAX_VIEWS],
}

/// `Draw`, the engine's push constants.
#[repr(C)]
#[derive(Clone, Copy)]
struct DrawPush {
    model: Mat4,
    colour: Vec4,
    first_view: u32,
}

/// One mesh of the world: its triangles and, in its own space, a sphere around them.
pub struct WorldMesh {
    pub vertices: Vec<EngineVertex>,
    pub indices: Vec<u32>,
    pub bounds: Sphere,
}

/// One object: a mesh placed in the world, with a colour.
pub struct WorldObject {
    pub mesh: usize,
    pub model: Mat4,
    pub colour: Vec4,
}

/// The engine's world, as its own data.
pub struct World {
    pub meshes: Vec<WorldMesh>,
    pub objects: Vec<WorldObject>,
    /// The direction the sunlight travels.
    pub light_dir: Vec3,
    /// Where the head starts: the file's camera, or a view framing the world.
    pub head: Mat4,
    /// How far from the head the world reaches (the far plane must reach as far).
    pub reach: f32,
}

impl World {
    /// A glTF file's world, flat shaded, imported with foveate's glTF loader (an engine would
    /// use its own importer; the GPU side below is all the engine's).
    pub fn from_gltf(path: &Path) -> Result<World, Box<dyn std::error::Error>> {
        let scene = foveate::scene::load_gltf(path)?.with_shading(Shading::Flat);
        let meshes = scene
            .meshes
            .iter()
            .map(|m| {
                let vertices: Vec<EngineVertex> = (m.vertices.iter())
                    .map(|v| EngineVertex {
                        position: v.position,
                        normal: v.normal,
                    })
                    .collect();
                WorldMesh {
                    bounds: bounding_sphere(&vertices),
                    vertices,
                    indices: m.indices.clone(),
                }
            })
            .collect();
        let objects = (scene.batches.iter())
            .flat_map(|b| {
                (b.instances.iter()).map(|i| WorldObject {
                    mesh: b.mesh,
                    model: i.model,
                    colour: i.color,
                })
            })
            .collect();
        Ok(World {
            meshes,
            objects,
            light_dir: scene.light_dir,
            head: scene.head,
            reach: scene.content_reach(),
        })
    }
}

/// A sphere around `vertices` (their box's centre, the farthest vertex from it).
fn bounding_sphere(vertices: &[EngineVertex]) -> Sphere {
    let points = vertices.iter().map(|v| Vec3::from(v.position));
    let (lo, hi) = points.clone().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    );
    let center = (lo + hi) * 0.5;
    let radius = points.map(|p| p.distance(center)).fold(0.0, f32::max);
    Sphere::new(center, radius)
}

/// A host-visible buffer and its memory, mapped.
struct HostBuffer {
    buffer: vk::Buffer,
    memory: vk::DeviceMemory,
    mapped: *mut u8,
}

/// Where each mesh lies in the engine's vertex and index buffers.
struct MeshRange {
    first_index: u32,
    index_count: u32,
    vertex_offset: i32,
}

/// The engine's GPU side.
pub struct Engine {
    gpu: Gpu,
    device: ash::Device,
    vertices: HostBuffer,
    indices: HostBuffer,
    /// One per frame slot.
    frames: Vec<HostBuffer>,
    set_layout: vk::DescriptorSetLayout,
    pool: vk::DescriptorPool,
    sets: Vec<vk::DescriptorSet>,
    layout: vk::PipelineLayout,
    shaders: [vk::ShaderModule; 2],
    /// Per pass it draws into (`DrawPass::index`), its pipeline.
    pipelines: Vec<(usize, vk::Pipeline)>,
    ranges: Vec<MeshRange>,
    world: World,
    /// Objects drawn in the last frame, all passes together.
    pub drawn: u64,
    /// Per frame view ([`View::index`]), a colour its surfaces are tinted with (alpha: how
    /// much; none unless set): which view drew what, for a debugging eye or a test.
    pub view_tints: [Vec4; MAX_VIEWS],
}

impl Engine {
    /// The engine's resources for `world` on `gpu`, a pipeline for each of `passes` (made as
    /// each describes: its render pass, samples and stencil test), `slots` frames in flight.
    pub fn new(
        gpu: &Gpu,
        world: World,
        passes: &[DrawPass],
        slots: usize,
    ) -> Result<Engine, Box<dyn std::error::Error>> {
        // The memory types the engine allocates its buffers from: foveate's instance and
        // physical device (an engine with a device of its own lends it: `Gpu::from_engine`).
        let physical = gpu.raw_handles().physical;
        // SAFETY: the physical device is the instance's.
        let memory = unsafe {
            gpu.instance()
                .get_physical_device_memory_properties(physical)
        };
        let device = gpu.device().clone();
        let vertex_data: Vec<EngineVertex> = (world.meshes.iter())
            .flat_map(|m| m.vertices.iter().copied())
            .collect();
        let index_data: Vec<u32> = (world.meshes.iter())
            .flat_map(|m| m.indices.iter().copied())
            .collect();
        let mut ranges = Vec::new();
        let (mut first_index, mut vertex_offset) = (0u32, 0i32);
        for m in &world.meshes {
            let index_count = m.indices.len() as u32;
            ranges.push(MeshRange {
                first_index,
                index_count,
                vertex_offset,
            });
            first_index += index_count;
            vertex_offset += m.vertices.len() as i32;
        }
        let buffer = |bytes: u64, usage| host_buffer(&device, &memory, bytes.max(16), usage);
        let vertices = buffer(
            std::mem::size_of_val(vertex_data.as_slice()) as u64,
            vk::BufferUsageFlags::VERTEX_BUFFER,
        )?;
        let indices = buffer(
            std::mem::size_of_val(index_data.as_slice()) as u64,
            vk::BufferUsageFlags::INDEX_BUFFER,
        )?;
        // SAFETY: each mapping holds at least the bytes copied.
        unsafe {
            copy_to(&vertices, &vertex_data);
            copy_to(&indices, &index_data);
        }
        let frames = (0..slots)
            .map(|_| {
                let bytes = std::mem::size_of::<FrameBlock>() as u64;
                buffer(bytes, vk::BufferUsageFlags::UNIFORM_BUFFER)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let (set_layout, pool, sets) = descriptor_sets(&device, &frames)?;
        let layout = pipeline_layout(&device, set_layout)?;
        let shaders = [
            shader(&device, VERTEX_SHADER)?,
            shader(&device, FRAGMENT_SHADER)?,
        ];
        let mut engine = Engine {
            gpu: gpu.clone(),
            device,
            vertices,
            indices,
            frames,
            set_layout,
            pool,
            sets,
            layout,
            shaders,
            pipelines: Vec::new(),
            ranges,
            world,
            drawn: 0,
            view_tints: [Vec4::ZERO; MAX_VIEWS],
        };
        for pass in passes {
            let pipeline = pipeline(&engine.device, engine.layout, engine.shaders, pass)?;
            engine.pipelines.push((pass.index, pipeline));
        }
        Ok(engine)
    }

    /// Writes frame slot `slot`'s block from the frame's views (before the frame records).
    pub fn write_views(&mut self, slot: usize, views: &[View]) {
        let mut block = FrameBlock {
            clip_from_world: [Mat4::IDENTITY; MAX_VIEWS],
            light_dir: self.world.light_dir.extend(0.0),
            view_tint: self.view_tints,
        };
        for v in views.iter().take(MAX_VIEWS) {
            block.clip_from_world[v.index] = v.clip_from_world;
        }
        // SAFETY: the slot's buffer holds one block; its last frame has finished.
        unsafe { copy_to(&self.frames[slot], &[block]) };
        self.drawn = 0;
    }

    /// Draws the world into the pass `ctx` describes: every object whose sphere meets the
    /// pass's superfrustum, once for all the pass's views (multiview).
    pub fn draw(&mut self, ctx: &DrawContext) {
        let Some(&(_, pipeline)) = self.pipelines.iter().find(|(i, _)| *i == ctx.pass.index) else {
            return;
        };
        let (d, cmd) = (&self.device, ctx.cmd);
        let view = &ctx.views[0];
        // SAFETY: recording inside the pass, with the engine's own objects, alive until the
        // frame has finished (the engine outlives its frames).
        unsafe {
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
            d.cmd_set_viewport(cmd, 0, &[view.viewport]);
            d.cmd_set_scissor(cmd, 0, &[view.scissor]);
            let set = [self.sets[ctx.slot]];
            let point = vk::PipelineBindPoint::GRAPHICS;
            d.cmd_bind_descriptor_sets(cmd, point, self.layout, 0, &set, &[]);
            d.cmd_bind_vertex_buffers(cmd, 0, &[self.vertices.buffer], &[0]);
            d.cmd_bind_index_buffer(cmd, self.indices.buffer, 0, vk::IndexType::UINT32);
        }
        for object in &self.world.objects {
            let bounds = self.world.meshes[object.mesh].bounds;
            let (scale, _, _) = object.model.to_scale_rotation_translation();
            let sphere = Sphere::new(
                object.model.transform_point3(bounds.center),
                bounds.radius * scale.abs().max_element(),
            );
            if !ctx.superfrustum.intersects_sphere(&sphere) {
                continue;
            }
            let push = DrawPush {
                model: object.model,
                colour: object.colour,
                first_view: ctx.pass.views.start as u32,
            };
            let range = &self.ranges[object.mesh];
            // SAFETY: as above; the push constants are the layout's range.
            unsafe {
                let bytes = std::slice::from_raw_parts(
                    (&push as *const DrawPush).cast::<u8>(),
                    std::mem::size_of::<DrawPush>(),
                );
                d.cmd_push_constants(cmd, self.layout, vk::ShaderStageFlags::VERTEX, 0, bytes);
                d.cmd_draw_indexed(
                    cmd,
                    range.index_count,
                    1,
                    range.first_index,
                    range.vertex_offset,
                    0,
                );
            }
            self.drawn += 1;
        }
    }
}

impl Drop for Engine {
    fn drop(&mut self) {
        // Nothing of the engine's may be in use by a frame still running.
        let _ = self.gpu.wait_idle();
        let d = &self.device;
        // SAFETY: the device is idle; every object is the engine's and destroyed once.
        unsafe {
            for (_, p) in &self.pipelines {
                d.destroy_pipeline(*p, None);
            }
            for s in self.shaders {
                d.destroy_shader_module(s, None);
            }
            d.destroy_pipeline_layout(self.layout, None);
            d.destroy_descriptor_pool(self.pool, None);
            d.destroy_descriptor_set_layout(self.set_layout, None);
            for b in self.frames.iter().chain([&self.vertices, &self.indices]) {
                d.destroy_buffer(b.buffer, None);
                d.free_memory(b.memory, None);
            }
        }
    }
}

/// Copies `data` into `buffer`'s mapping.
///
/// # Safety
/// The mapping holds at least `data`'s bytes, and the GPU does not read them meanwhile.
unsafe fn copy_to<T: Copy>(buffer: &HostBuffer, data: &[T]) {
    let bytes = std::mem::size_of_val(data);
    std::ptr::copy_nonoverlapping(data.as_ptr().cast::<u8>(), buffer.mapped, bytes);
}

/// A host-visible, coherent buffer of `bytes`, mapped.
fn host_buffer(
    device: &ash::Device,
    memory: &vk::PhysicalDeviceMemoryProperties,
    bytes: u64,
    usage: vk::BufferUsageFlags,
) -> Result<HostBuffer, vk::Result> {
    let wanted = vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT;
    // SAFETY: plain object creation on a live device; the memory is bound and mapped once.
    unsafe {
        let info = vk::BufferCreateInfo::default().size(bytes).usage(usage);
        let buffer = device.create_buffer(&info, None)?;
        let needs = device.get_buffer_memory_requirements(buffer);
        let kind = (0..memory.memory_type_count)
            .find(|&i| {
                needs.memory_type_bits & (1 << i) != 0
                    && memory.memory_types[i as usize]
                        .property_flags
                        .contains(wanted)
            })
            .ok_or(vk::Result::ERROR_OUT_OF_DEVICE_MEMORY)?;
        let allocate = vk::MemoryAllocateInfo::default()
            .allocation_size(needs.size)
            .memory_type_index(kind);
        let memory = device.allocate_memory(&allocate, None)?;
        device.bind_buffer_memory(buffer, memory, 0)?;
        let mapped = device.map_memory(memory, 0, vk::WHOLE_SIZE, vk::MemoryMapFlags::empty())?;
        Ok(HostBuffer {
            buffer,
            memory,
            mapped: mapped.cast(),
        })
    }
}

/// One uniform binding (the frame block) for both stages, a set per frame slot.
#[allow(clippy::type_complexity)]
fn descriptor_sets(
    device: &ash::Device,
    frames: &[HostBuffer],
) -> Result<
    (
        vk::DescriptorSetLayout,
        vk::DescriptorPool,
        Vec<vk::DescriptorSet>,
    ),
    vk::Result,
> {
    let binding = [vk::DescriptorSetLayoutBinding::default()
        .binding(0)
        .descriptor_type(vk::DescriptorType::UNIFORM_BUFFER)
        .descriptor_count(1)
        .stage_flags(vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT)];
    let sizes = [vk::DescriptorPoolSize {
        ty: vk::DescriptorType::UNIFORM_BUFFER,
        descriptor_count: frames.len() as u32,
    }];
    // SAFETY: plain object creation; each set is written once, before any use.
    unsafe {
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&binding);
        let layout = device.create_descriptor_set_layout(&info, None)?;
        let info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(frames.len() as u32)
            .pool_sizes(&sizes);
        let pool = device.create_descriptor_pool(&info, None)?;
        let layouts = vec![layout; frames.len()];
        let info = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(pool)
            .set_layouts(&layouts);
        let sets = device.allocate_descriptor_sets(&info)?;
        for (set, frame) in sets.iter().zip(frames) {
            let buffer = [vk::DescriptorBufferInfo {
                buffer: frame.buffer,
                offset: 0,
                range: std::mem::size_of::<FrameBlock>() as u64,
            }];
            let write = vk::WriteDescriptorSet::default()
                .dst_set(*set)
                .dst_binding(0)
                .descriptor_type(vk::DescriptorType::UNIFORM_BUFFER)
                .buffer_info(&buffer);
            device.update_descriptor_sets(&[write], &[]);
        }
        Ok((layout, pool, sets))
    }
}

/// The frame block's set and the per-draw push constants (vertex stage).
fn pipeline_layout(
    device: &ash::Device,
    set: vk::DescriptorSetLayout,
) -> Result<vk::PipelineLayout, vk::Result> {
    let push = [vk::PushConstantRange {
        stage_flags: vk::ShaderStageFlags::VERTEX,
        offset: 0,
        size: std::mem::size_of::<DrawPush>() as u32,
    }];
    let sets = [set];
    let info = vk::PipelineLayoutCreateInfo::default()
        .set_layouts(&sets)
        .push_constant_ranges(&push);
    // SAFETY: plain object creation.
    unsafe { device.create_pipeline_layout(&info, None) }
}

fn shader(
    device: &ash::Device,
    spirv: &[u8],
) -> Result<vk::ShaderModule, Box<dyn std::error::Error>> {
    let words = ash::util::read_spv(&mut std::io::Cursor::new(spirv))?;
    let info = vk::ShaderModuleCreateInfo::default().code(&words);
    // SAFETY: plain object creation from valid SPIR-V.
    Ok(unsafe { device.create_shader_module(&info, None) }?)
}

/// The engine's pipeline for `pass`: its render pass and samples, depth tested and written
/// (reverse-Z: nearer is greater), back faces culled, and the pass's stencil test.
fn pipeline(
    device: &ash::Device,
    layout: vk::PipelineLayout,
    shaders: [vk::ShaderModule; 2],
    pass: &DrawPass,
) -> Result<vk::Pipeline, vk::Result> {
    let stages = [
        (vk::ShaderStageFlags::VERTEX, shaders[0]),
        (vk::ShaderStageFlags::FRAGMENT, shaders[1]),
    ]
    .map(|(stage, module)| {
        vk::PipelineShaderStageCreateInfo::default()
            .stage(stage)
            .module(module)
            .name(c"main")
    });
    let bindings = [vk::VertexInputBindingDescription {
        binding: 0,
        stride: std::mem::size_of::<EngineVertex>() as u32,
        input_rate: vk::VertexInputRate::VERTEX,
    }];
    let attributes = [0, 12].map(|offset| vk::VertexInputAttributeDescription {
        location: offset / 12,
        binding: 0,
        format: vk::Format::R32G32B32_SFLOAT,
        offset,
    });
    let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
        .vertex_binding_descriptions(&bindings)
        .vertex_attribute_descriptions(&attributes);
    let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
        .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
    let viewport = vk::PipelineViewportStateCreateInfo::default()
        .viewport_count(1)
        .scissor_count(1);
    let raster = vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(vk::PolygonMode::FILL)
        .cull_mode(vk::CullModeFlags::BACK)
        .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
        .line_width(1.0);
    let multisample =
        vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(pass.samples);
    let depth = vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(true)
        .depth_write_enable(true)
        .depth_compare_op(vk::CompareOp::GREATER)
        .stencil_test_enable(pass.stencil.is_some())
        .front(pass.stencil.unwrap_or_default())
        .back(pass.stencil.unwrap_or_default());
    let attachment = [vk::PipelineColorBlendAttachmentState::default()
        .color_write_mask(vk::ColorComponentFlags::RGBA)];
    let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&attachment);
    let dynamic = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
    let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic);
    let info = vk::GraphicsPipelineCreateInfo::default()
        .stages(&stages)
        .vertex_input_state(&vertex_input)
        .input_assembly_state(&assembly)
        .viewport_state(&viewport)
        .rasterization_state(&raster)
        .multisample_state(&multisample)
        .depth_stencil_state(&depth)
        .color_blend_state(&blend)
        .dynamic_state(&dynamic)
        .layout(layout)
        .render_pass(pass.render_pass)
        .subpass(0);
    // SAFETY: every state the info points at lives on this stack frame for the call.
    let made =
        unsafe { device.create_graphics_pipelines(vk::PipelineCache::null(), &[info], None) };
    made.map(|p| p[0]).map_err(|(_, e)| e)
}
