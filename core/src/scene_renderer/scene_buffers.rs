use ash::vk;

use crate::foveation_layer::vulkan_recorder::{MeshRange, SceneGeometry};
use crate::gpu::{memory_barrier, pod_bytes, Buffer, Gpu, GpuError, MemoryLocation};
use crate::plan::FramePlan;
use crate::scene::{Draw, Scene, Shading, Vertex};

/// The scene on the GPU: all meshes in one vertex and one index buffer, all instances in one
/// storage buffer, and the draw list.
pub(crate) struct SceneBuffers {
    pub vertices: Buffer,
    pub indices: Buffer,
    pub instances: Buffer,
    /// The ranges a [`Draw`]'s `mesh` names: each whole mesh, then each mesh's clusters, then
    /// each mesh's simplified levels.
    pub meshes: Vec<MeshRange>,
    /// Where each mesh's clusters start in `meshes`.
    pub first_cluster: Vec<usize>,
    /// Where each mesh's simplified levels start in `meshes`.
    pub first_lod: Vec<usize>,
    pub draws: Vec<Draw>,
}

impl SceneBuffers {
    /// The geometry as the layer draws the scene's steps from it.
    pub fn geometry(&self) -> SceneGeometry<'_> {
        SceneGeometry {
            vertices: self.vertices.raw,
            indices: self.indices.raw,
            meshes: &self.meshes,
        }
    }

    pub fn upload(gpu: &Gpu, scene: &Scene) -> Result<Self, GpuError> {
        let mut vertices: Vec<Vertex> = Vec::new();
        let mut indices: Vec<u32> = Vec::new();
        let mut meshes: Vec<MeshRange> = scene
            .meshes
            .iter()
            .map(|m| {
                let range = MeshRange {
                    first_index: indices.len() as u32,
                    index_count: m.indices.len() as u32,
                    vertex_offset: vertices.len() as i32,
                };
                vertices.extend_from_slice(&m.vertices);
                indices.extend_from_slice(&m.indices);
                range
            })
            .collect();
        let mut first_cluster = Vec::with_capacity(scene.meshes.len());
        for (k, mesh) in scene.meshes.iter().enumerate() {
            first_cluster.push(meshes.len());
            let whole = meshes[k];
            meshes.extend(mesh.clusters.iter().map(|c| MeshRange {
                first_index: whole.first_index + c.first_index,
                index_count: c.index_count,
                vertex_offset: whole.vertex_offset,
            }));
        }
        let mut first_lod = Vec::with_capacity(scene.meshes.len());
        for (k, mesh) in scene.meshes.iter().enumerate() {
            first_lod.push(meshes.len());
            for level in &mesh.lods {
                meshes.push(MeshRange {
                    first_index: indices.len() as u32,
                    index_count: level.indices.len() as u32,
                    vertex_offset: meshes[k].vertex_offset,
                });
                indices.extend_from_slice(&level.indices);
            }
        }
        let instances = scene.flat_instances();
        Ok(SceneBuffers {
            vertices: upload(
                gpu,
                "vertices",
                pod_bytes(&vertices),
                vk::BufferUsageFlags::VERTEX_BUFFER,
            )?,
            indices: upload(
                gpu,
                "indices",
                pod_bytes(&indices),
                vk::BufferUsageFlags::INDEX_BUFFER,
            )?,
            instances: upload(
                gpu,
                "instances",
                pod_bytes(&instances),
                vk::BufferUsageFlags::STORAGE_BUFFER,
            )?,
            meshes,
            first_cluster,
            first_lod,
            draws: scene.draws().collect(),
        })
    }
}

/// A device-local buffer filled through a staging copy, readable by every shader stage.
pub(super) fn upload(
    gpu: &Gpu,
    name: &str,
    bytes: &[u8],
    usage: vk::BufferUsageFlags,
) -> Result<Buffer, GpuError> {
    let size = bytes.len().max(4) as u64;
    let mut staging = Buffer::new(
        gpu,
        "staging",
        size,
        vk::BufferUsageFlags::TRANSFER_SRC,
        MemoryLocation::CpuToGpu,
    )?;
    staging.mapped()[..bytes.len()].copy_from_slice(bytes);
    let buffer = Buffer::new(
        gpu,
        name,
        size,
        usage | vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuOnly,
    )?;
    gpu.one_shot(|cmd| {
        let region = [vk::BufferCopy {
            src_offset: 0,
            dst_offset: 0,
            size,
        }];
        // SAFETY: both buffers are alive until one_shot has waited for the copy.
        unsafe {
            gpu.device()
                .cmd_copy_buffer(cmd, staging.raw, buffer.raw, &region)
        };
        // SAFETY: recorded into one_shot's command buffer.
        unsafe {
            memory_barrier(
                gpu.device(),
                cmd,
                (
                    vk::PipelineStageFlags::TRANSFER,
                    vk::AccessFlags::TRANSFER_WRITE,
                ),
                (
                    vk::PipelineStageFlags::VERTEX_INPUT
                        | vk::PipelineStageFlags::VERTEX_SHADER
                        | vk::PipelineStageFlags::FRAGMENT_SHADER,
                    vk::AccessFlags::VERTEX_ATTRIBUTE_READ
                        | vk::AccessFlags::INDEX_READ
                        | vk::AccessFlags::SHADER_READ,
                ),
            )
        };
    })?;
    Ok(buffer)
}

/// The scene must be the one the plan was made for (its buffers are sized for it).
pub(super) fn check_scene(plan: &FramePlan, scene: &Scene) -> Result<(), GpuError> {
    if scene.instance_count() != plan.scene_instances {
        return Err(crate::vocab::ConfigError::new(
            "scene",
            format!("{} instances", scene.instance_count()),
            format!(
                "the scene the plan was made for ({} instances): plan the frame for this scene",
                plan.scene_instances
            ),
        )
        .into());
    }
    let counts = |c: crate::plan::ClusterPlan| (c.clusters, c.meshes, c.max_triangles);
    if !plan.cull_slots.is_empty()
        && plan.clusters.map(counts) != crate::plan::cluster_plan(scene).map(counts)
    {
        return Err(crate::vocab::ConfigError::new(
            "scene",
            format!("{} clusters", scene.cluster_counts().0),
            "the clusters the plan was made for: plan the frame for this scene",
        )
        .into());
    }
    let levels = |l: crate::plan::LodPlan| (l.levels, l.meshes);
    if plan.lod.is_some() && plan.lod.map(levels) != Some(scene.lod_counts()) {
        return Err(crate::vocab::ConfigError::new(
            "scene",
            format!("{} simplified levels", scene.lod_counts().0),
            "the levels of detail the plan was made for: plan the frame for this scene",
        )
        .into());
    }
    if scene.shading() == Shading::Lit && !plan.lit || scene.shading() == Shading::Flat && plan.lit
    {
        return Err(crate::vocab::ConfigError::new(
            "scene",
            format!("{} shading", scene.shading()),
            "the shading the plan was made for: plan the frame for this scene",
        )
        .into());
    }
    Ok(())
}
