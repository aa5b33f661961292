//! The driver's own statistics of every pipeline foveate compiles, where the device offers
//! `VK_KHR_pipeline_executable_properties` (Mesa's turnip for Adreno, RADV, NVIDIA's driver; no
//! lavapipe): per executable (a vertex shader, a fragment shader, a tile GPU's binning-pass
//! vertex shader …) the figures its compiler reports (instructions, registers, waves, …), by the
//! driver's own names. Nothing is asked of a device without the extension.

use std::ffi::CStr;

use ash::vk;

use super::{GpuError, VkResultExt};

/// The extension that reports them.
pub(crate) const EXTENSION: &CStr = ash::khr::pipeline_executable_properties::NAME;

/// One statistic of an executable, as its driver names and counts it.
#[derive(Clone, Debug, PartialEq)]
pub struct ShaderStatistic {
    /// The driver's name for it ("Instruction Count", "Max Waves Per Core" on turnip).
    pub name: String,
    /// The driver's description of it.
    pub description: String,
    /// Its value.
    pub value: StatisticValue,
}

/// A statistic's value, in the type its driver reports.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StatisticValue {
    /// A yes or no.
    Bool(bool),
    /// A signed count.
    Int(i64),
    /// An unsigned count.
    Uint(u64),
    /// A measure.
    Float(f64),
}

impl StatisticValue {
    /// The value as a number (a yes is 1).
    pub fn as_f64(self) -> f64 {
        match self {
            StatisticValue::Bool(b) => f64::from(u8::from(b)),
            StatisticValue::Int(v) => v as f64,
            StatisticValue::Uint(v) => v as f64,
            StatisticValue::Float(v) => v,
        }
    }
}

impl std::fmt::Display for StatisticValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            StatisticValue::Bool(b) => write!(f, "{}", if *b { "yes" } else { "no" }),
            StatisticValue::Int(v) => write!(f, "{v}"),
            StatisticValue::Uint(v) => write!(f, "{v}"),
            StatisticValue::Float(v) => write!(f, "{v}"),
        }
    }
}

/// One executable of a compiled pipeline: a program the driver made of its shaders.
#[derive(Clone, Debug, PartialEq)]
pub struct ShaderExecutable {
    /// The driver's short name for it ("VS", "FS", "Binning VS" on turnip).
    pub name: String,
    /// The driver's description of it.
    pub description: String,
    /// The shader stages it runs.
    pub stages: vk::ShaderStageFlags,
    /// The subgroup size it runs at (0 where the driver does not say).
    pub subgroup_size: u32,
    /// Its statistics, in the driver's order.
    pub statistics: Vec<ShaderStatistic>,
}

impl ShaderExecutable {
    /// The statistic of this name, if the driver reports it.
    pub fn statistic(&self, name: &str) -> Option<StatisticValue> {
        self.statistics
            .iter()
            .find(|s| s.name == name)
            .map(|s| s.value)
    }
}

/// The statistics of `pipeline`, created with `VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR`
/// on a device with the extension and its `pipelineExecutableInfo` feature enabled.
pub(crate) fn capture(
    ext: &ash::khr::pipeline_executable_properties::Device,
    pipeline: vk::Pipeline,
) -> Result<Vec<ShaderExecutable>, GpuError> {
    let info = vk::PipelineInfoKHR::default().pipeline(pipeline);
    // SAFETY: the pipeline is alive and was created with statistics captured.
    let executables = unsafe { ext.get_pipeline_executable_properties(&info) }
        .vk("vkGetPipelineExecutablePropertiesKHR")?;
    (0u32..)
        .zip(executables)
        .map(|(index, properties)| {
            let info = vk::PipelineExecutableInfoKHR::default()
                .pipeline(pipeline)
                .executable_index(index);
            // SAFETY: as above; `index` is one of the pipeline's executables.
            let statistics = unsafe { ext.get_pipeline_executable_statistics(&info) }
                .vk("vkGetPipelineExecutableStatisticsKHR")?;
            Ok(ShaderExecutable {
                name: text(&properties.name),
                description: text(&properties.description),
                stages: properties.stages,
                subgroup_size: properties.subgroup_size,
                statistics: statistics.iter().map(statistic).collect(),
            })
        })
        .collect()
}

fn statistic(s: &vk::PipelineExecutableStatisticKHR) -> ShaderStatistic {
    use vk::PipelineExecutableStatisticFormatKHR as Format;
    // SAFETY: the union's member is the one `format` names.
    let value = unsafe {
        match s.format {
            Format::BOOL32 => StatisticValue::Bool(s.value.b32 == vk::TRUE),
            Format::INT64 => StatisticValue::Int(s.value.i64),
            Format::UINT64 => StatisticValue::Uint(s.value.u64),
            _ => StatisticValue::Float(s.value.f64),
        }
    };
    ShaderStatistic {
        name: text(&s.name),
        description: text(&s.description),
        value,
    }
}

/// A fixed-size, NUL-terminated string from the driver.
fn text(chars: &[std::ffi::c_char]) -> String {
    let bytes: Vec<u8> = chars
        .iter()
        .take_while(|&&c| c != 0)
        .map(|&c| c as u8)
        .collect();
    String::from_utf8_lossy(&bytes).into_owned()
}

/// Whether `physical`, which offers the extension where `extension_offered`, has its
/// `pipelineExecutableInfo` feature: foveate then enables both on the devices it opens.
pub(crate) fn offered(
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
    extension_offered: bool,
) -> bool {
    if !extension_offered {
        return false;
    }
    let mut feature = vk::PhysicalDevicePipelineExecutablePropertiesFeaturesKHR::default();
    let mut features = vk::PhysicalDeviceFeatures2::default().push_next(&mut feature);
    // SAFETY: a query on a valid physical device of a Vulkan 1.1 instance.
    unsafe { instance.get_physical_device_features2(physical, &mut features) };
    feature.pipeline_executable_info == vk::TRUE
}

impl super::Gpu {
    /// Whether the device reports its compiler's statistics for the pipelines foveate
    /// creates (`VK_KHR_pipeline_executable_properties` on a device foveate opened).
    pub fn shader_statistics_offered(&self) -> bool {
        self.executable_properties.is_some()
    }

    /// The flags a pipeline is created with: capturing its statistics where the device reports
    /// them (`VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR`), nothing else.
    pub(crate) fn statistics_flags(&self) -> vk::PipelineCreateFlags {
        match self.executable_properties {
            Some(_) => vk::PipelineCreateFlags::CAPTURE_STATISTICS_KHR,
            None => vk::PipelineCreateFlags::empty(),
        }
    }

    /// Takes ownership of `raw`, created on this device with [`Self::statistics_flags`], with
    /// its statistics read where the device reports them.
    pub(crate) fn pipeline_with_statistics(
        &self,
        raw: vk::Pipeline,
    ) -> Result<super::Pipeline, GpuError> {
        let mut pipeline = super::Pipeline::from_raw(&self.dev, raw);
        if let Some(ext) = &self.executable_properties {
            pipeline.statistics = Some(capture(ext, pipeline.raw)?);
        }
        Ok(pipeline)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn driver_statistic(
        name: &str,
        format: vk::PipelineExecutableStatisticFormatKHR,
        value: vk::PipelineExecutableStatisticValueKHR,
    ) -> vk::PipelineExecutableStatisticKHR<'static> {
        let mut s = vk::PipelineExecutableStatisticKHR::default();
        for (to, from) in s.name.iter_mut().zip(name.bytes()) {
            *to = from as std::ffi::c_char;
        }
        s.format = format;
        s.value = value;
        s
    }

    /// The driver's statistics as turnip reports them for the Adreno 650's lit scene shader
    /// (recorded: "Instruction Count" 1171 as UINT64, "Early preamble" as BOOL32), and a signed
    /// and a float one: each read from the union member its format names, its name up to the
    /// NUL. Mutation: a format mapped to another member (a float read as an integer) fails it.
    #[test]
    fn each_statistic_is_read_as_its_format_says() {
        use vk::PipelineExecutableStatisticFormatKHR as F;
        use vk::PipelineExecutableStatisticValueKHR as V;
        let read = |s| statistic(&s);
        let count = read(driver_statistic(
            "Instruction Count",
            F::UINT64,
            V { u64: 1171 },
        ));
        assert_eq!(count.name, "Instruction Count");
        assert_eq!(count.value, StatisticValue::Uint(1171));
        let early = read(driver_statistic(
            "Early preamble",
            F::BOOL32,
            V { b32: vk::TRUE },
        ));
        assert_eq!(early.value, StatisticValue::Bool(true));
        assert_eq!(early.value.as_f64(), 1.0);
        let signed = read(driver_statistic("Signed", F::INT64, V { i64: -3 }));
        assert_eq!(signed.value, StatisticValue::Int(-3));
        let float = read(driver_statistic("Occupancy", F::FLOAT64, V { f64: 0.75 }));
        assert_eq!(float.value, StatisticValue::Float(0.75));
        assert_eq!(float.value.to_string(), "0.75");
    }
}
