/* The fewest Vulkan calls that leak host memory on lavapipe 22.3 and not on 25.0: a 64x64 pass
 * that draws a full-view triangle with one fragment shader, frame after frame, and the process's
 * resident memory before and after.
 *
 *   leak FRAG.spv FRAMES DRAWS REBIND
 *
 * Each frame binds the pipeline and the descriptor set and pushes 16 bytes of push constants
 * once, then draws DRAWS times; before every further draw REBIND 1 binds the set again, 2 pushes
 * the constants again, 3 does both. The
 * calls are the same for every shader (run.sh builds one per candidate from leak.frag); only
 * what bounds the shader's loop differs. Prints the growth in KiB per frame after a warm-up.
 *
 * Build: cc -O2 -o leak leak.c -lvulkan (run.sh does, and runs every candidate on a driver).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <vulkan/vulkan.h>

#define CHECK(call)                                                                    \
    do {                                                                               \
        VkResult r_ = (call);                                                          \
        if (r_ != VK_SUCCESS) {                                                        \
            fprintf(stderr, "%s:%d: %s failed: %d\n", __FILE__, __LINE__, #call, r_); \
            exit(1);                                                                   \
        }                                                                              \
    } while (0)

enum { SIZE = 64, LAYERS = 2, LEVELS = 7, WARM_UP = 20 };

static VkDevice dev;
static VkPhysicalDeviceMemoryProperties mem_props;

static long resident_kib(void) {
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    long kib = -1;
    while (f && fgets(line, sizeof line, f))
        if (sscanf(line, "VmRSS: %ld kB", &kib) == 1)
            break;
    if (f)
        fclose(f);
    return kib;
}

static VkShaderModule shader(const char *path) {
    FILE *f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "cannot open %s\n", path);
        exit(1);
    }
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fseek(f, 0, SEEK_SET);
    uint32_t *code = malloc(size);
    if (fread(code, 1, size, f) != (size_t)size)
        exit(1);
    fclose(f);
    VkShaderModuleCreateInfo info = {VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO, NULL, 0, size, code};
    VkShaderModule module;
    CHECK(vkCreateShaderModule(dev, &info, NULL, &module));
    free(code);
    return module;
}

static VkDeviceMemory bind_memory(VkMemoryRequirements req, VkMemoryPropertyFlags want) {
    for (uint32_t i = 0; i < mem_props.memoryTypeCount; i++) {
        if ((req.memoryTypeBits & (1u << i)) && (mem_props.memoryTypes[i].propertyFlags & want) == want) {
            VkMemoryAllocateInfo info = {VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO, NULL, req.size, i};
            VkDeviceMemory memory;
            CHECK(vkAllocateMemory(dev, &info, NULL, &memory));
            return memory;
        }
    }
    fprintf(stderr, "no memory type\n");
    exit(1);
}

static VkImage image(VkFormat format, uint32_t layers, uint32_t levels, VkImageUsageFlags usage) {
    VkImageCreateInfo info = {VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = (VkExtent3D){SIZE, SIZE, 1};
    info.mipLevels = levels;
    info.arrayLayers = layers;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = usage;
    VkImage img;
    CHECK(vkCreateImage(dev, &info, NULL, &img));
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(dev, img, &req);
    CHECK(vkBindImageMemory(dev, img, bind_memory(req, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT), 0));
    return img;
}

static VkImageView view(VkImage img, VkImageViewType type, VkFormat format, uint32_t layers, uint32_t levels) {
    VkImageViewCreateInfo info = {VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    info.image = img;
    info.viewType = type;
    info.format = format;
    info.subresourceRange = (VkImageSubresourceRange){VK_IMAGE_ASPECT_COLOR_BIT, 0, levels, 0, layers};
    VkImageView v;
    CHECK(vkCreateImageView(dev, &info, NULL, &v));
    return v;
}

static VkBuffer buffer(VkBufferUsageFlags usage, const void *data, VkDeviceSize size) {
    VkBufferCreateInfo info = {VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO, NULL, 0, size, usage};
    VkBuffer buf;
    CHECK(vkCreateBuffer(dev, &info, NULL, &buf));
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(dev, buf, &req);
    VkDeviceMemory memory = bind_memory(req, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    CHECK(vkBindBufferMemory(dev, buf, memory, 0));
    void *mapped;
    CHECK(vkMapMemory(dev, memory, 0, size, 0, &mapped));
    memcpy(mapped, data, size);
    return buf;
}

static VkPipeline pipeline(const char *frag, VkRenderPass pass, VkPipelineLayout layout) {
    uint32_t count = 4;
    VkSpecializationMapEntry entry = {0, 0, sizeof count};
    VkSpecializationInfo spec = {1, &entry, sizeof count, &count};
    VkPipelineShaderStageCreateInfo stages[2] = {
        {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, NULL, 0, VK_SHADER_STAGE_VERTEX_BIT, shader("leak.vert.spv"), "main"},
        {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, NULL, 0, VK_SHADER_STAGE_FRAGMENT_BIT, shader(frag), "main", &spec},
    };
    VkPipelineVertexInputStateCreateInfo vertices = {VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    VkPipelineInputAssemblyStateCreateInfo assembly = {VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO, NULL, 0, VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST};
    VkViewport vp = {0, 0, SIZE, SIZE, 0, 1};
    VkRect2D scissor = {{0, 0}, {SIZE, SIZE}};
    VkPipelineViewportStateCreateInfo viewport = {VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO, NULL, 0, 1, &vp, 1, &scissor};
    VkPipelineRasterizationStateCreateInfo raster = {VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    raster.lineWidth = 1;
    VkPipelineMultisampleStateCreateInfo msaa = {VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO, NULL, 0, VK_SAMPLE_COUNT_1_BIT};
    VkPipelineColorBlendAttachmentState blend = {0};
    blend.colorWriteMask = 0xf;
    VkPipelineColorBlendStateCreateInfo blending = {VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    blending.attachmentCount = 1;
    blending.pAttachments = &blend;
    VkGraphicsPipelineCreateInfo info = {VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
    info.stageCount = 2;
    info.pStages = stages;
    info.pVertexInputState = &vertices;
    info.pInputAssemblyState = &assembly;
    info.pViewportState = &viewport;
    info.pRasterizationState = &raster;
    info.pMultisampleState = &msaa;
    info.pColorBlendState = &blending;
    info.layout = layout;
    info.renderPass = pass;
    VkPipeline p;
    CHECK(vkCreateGraphicsPipelines(dev, VK_NULL_HANDLE, 1, &info, NULL, &p));
    return p;
}

int main(int argc, char **argv) {
    if (argc != 5) {
        fprintf(stderr, "usage: leak FRAG.spv FRAMES DRAWS REBIND\n");
        return 2;
    }
    int frames = atoi(argv[2]), draws = atoi(argv[3]), rebind = atoi(argv[4]);
    VkApplicationInfo app = {VK_STRUCTURE_TYPE_APPLICATION_INFO, NULL, "leak", 1, NULL, 0, VK_API_VERSION_1_1};
    VkInstanceCreateInfo instance_info = {VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO, NULL, 0, &app};
    VkInstance instance;
    CHECK(vkCreateInstance(&instance_info, NULL, &instance));
    uint32_t one = 1;
    VkPhysicalDevice gpu;
    vkEnumeratePhysicalDevices(instance, &one, &gpu);
    vkGetPhysicalDeviceMemoryProperties(gpu, &mem_props);
    float priority = 1;
    VkDeviceQueueCreateInfo queue_info = {VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO, NULL, 0, 0, 1, &priority};
    VkDeviceCreateInfo device_info = {VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, NULL, 0, 1, &queue_info};
    CHECK(vkCreateDevice(gpu, &device_info, NULL, &dev));
    VkQueue queue;
    vkGetDeviceQueue(dev, 0, 0, &queue);

    /* The target, and a sampled 2D array with a full mip chain (the lit scene's kind). */
    VkFormat rgba = VK_FORMAT_R8G8B8A8_UNORM;
    VkImage target = image(rgba, 1, 1, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT);
    VkImageView target_view = view(target, VK_IMAGE_VIEW_TYPE_2D, rgba, 1, 1);
    VkImage texture = image(rgba, LAYERS, LEVELS, VK_IMAGE_USAGE_SAMPLED_BIT);
    VkImageView texture_view = view(texture, VK_IMAGE_VIEW_TYPE_2D_ARRAY, rgba, LAYERS, LEVELS);
    VkSamplerCreateInfo sampler_info = {VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    sampler_info.magFilter = sampler_info.minFilter = VK_FILTER_LINEAR;
    sampler_info.mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
    sampler_info.maxLod = VK_LOD_CLAMP_NONE;
    VkSampler sampler;
    CHECK(vkCreateSampler(dev, &sampler_info, NULL, &sampler));

    VkAttachmentDescription attachment = {0, rgba, VK_SAMPLE_COUNT_1_BIT, VK_ATTACHMENT_LOAD_OP_CLEAR, VK_ATTACHMENT_STORE_OP_STORE,
                                          VK_ATTACHMENT_LOAD_OP_DONT_CARE, VK_ATTACHMENT_STORE_OP_DONT_CARE,
                                          VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkAttachmentReference colour = {0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription subpass = {0, VK_PIPELINE_BIND_POINT_GRAPHICS, 0, NULL, 1, &colour};
    VkRenderPassCreateInfo pass_info = {VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO, NULL, 0, 1, &attachment, 1, &subpass};
    VkRenderPass pass;
    CHECK(vkCreateRenderPass(dev, &pass_info, NULL, &pass));
    VkFramebufferCreateInfo fb_info = {VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO, NULL, 0, pass, 1, &target_view, SIZE, SIZE, 1};
    VkFramebuffer framebuffer;
    CHECK(vkCreateFramebuffer(dev, &fb_info, NULL, &framebuffer));

    /* One set: the lights (uniform buffer), a count in a storage buffer, the texture. */
    VkDescriptorSetLayoutBinding bindings[3] = {
        {0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT},
        {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT},
        {2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT},
    };
    VkDescriptorSetLayoutCreateInfo set_info = {VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO, NULL, 0, 3, bindings};
    VkDescriptorSetLayout set_layout;
    CHECK(vkCreateDescriptorSetLayout(dev, &set_info, NULL, &set_layout));
    VkPushConstantRange push_range = {VK_SHADER_STAGE_FRAGMENT_BIT, 0, 16};
    VkPipelineLayoutCreateInfo layout_info = {VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO, NULL, 0, 1, &set_layout, 1, &push_range};
    VkPipelineLayout layout;
    CHECK(vkCreatePipelineLayout(dev, &layout_info, NULL, &layout));
    VkDescriptorPoolSize sizes[3] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1}, {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1}, {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1}};
    VkDescriptorPoolCreateInfo pool_info = {VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO, NULL, 0, 1, 3, sizes};
    VkDescriptorPool pool;
    CHECK(vkCreateDescriptorPool(dev, &pool_info, NULL, &pool));
    VkDescriptorSetAllocateInfo alloc = {VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO, NULL, pool, 1, &set_layout};
    VkDescriptorSet set;
    CHECK(vkAllocateDescriptorSets(dev, &alloc, &set));
    float lights[20] = {0.3f, 0.2f, 0.1f, 0, 0.1f, 0.3f, 0.2f, 0, 0.2f, 0.1f, 0.3f, 0, 0.1f, 0.1f, 0.1f, 0};
    uint32_t count[4] = {4, 4, 0, 0};
    memcpy(&lights[16], count, sizeof count);
    VkBuffer uniforms = buffer(VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, lights, sizeof lights);
    VkBuffer storage = buffer(VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, count, sizeof count);
    VkDescriptorBufferInfo ubo = {uniforms, 0, VK_WHOLE_SIZE}, ssbo = {storage, 0, VK_WHOLE_SIZE};
    VkDescriptorImageInfo tex = {sampler, texture_view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    VkWriteDescriptorSet writes[3] = {
        {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, NULL, set, 0, 0, 1, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, NULL, &ubo},
        {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, NULL, set, 1, 0, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, NULL, &ssbo},
        {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, NULL, set, 2, 0, 1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, &tex},
    };
    vkUpdateDescriptorSets(dev, 3, writes, 0, NULL);
    VkPipeline pipe = pipeline(argv[1], pass, layout);

    VkCommandPoolCreateInfo cmd_pool_info = {VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO, NULL, VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT, 0};
    VkCommandPool cmd_pool;
    CHECK(vkCreateCommandPool(dev, &cmd_pool_info, NULL, &cmd_pool));
    VkCommandBufferAllocateInfo cmd_info = {VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO, NULL, cmd_pool, VK_COMMAND_BUFFER_LEVEL_PRIMARY, 1};
    VkCommandBuffer cmd;
    CHECK(vkAllocateCommandBuffers(dev, &cmd_info, &cmd));
    VkFenceCreateInfo fence_info = {VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkFence fence;
    CHECK(vkCreateFence(dev, &fence_info, NULL, &fence));

    long before = 0;
    for (int frame = 0; frame < WARM_UP + frames; frame++) {
        if (frame == WARM_UP)
            before = resident_kib();
        VkCommandBufferBeginInfo begin = {VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO, NULL, VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
        CHECK(vkBeginCommandBuffer(cmd, &begin));
        if (frame == 0) { /* the texture's layout, once (its texels stay undefined: never judged) */
            VkImageMemoryBarrier barrier = {VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER, NULL, 0, VK_ACCESS_SHADER_READ_BIT,
                                            VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                                            VK_QUEUE_FAMILY_IGNORED, VK_QUEUE_FAMILY_IGNORED, texture,
                                            {VK_IMAGE_ASPECT_COLOR_BIT, 0, LEVELS, 0, LAYERS}};
            vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, 0, 0, NULL, 0, NULL, 1, &barrier);
        }
        VkClearValue clear = {{{0, 0, 0, 1}}};
        VkRenderPassBeginInfo rp = {VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO, NULL, pass, framebuffer, {{0, 0}, {SIZE, SIZE}}, 1, &clear};
        vkCmdBeginRenderPass(cmd, &rp, VK_SUBPASS_CONTENTS_INLINE);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipe);
        for (int d = 0; d < draws; d++) {
            if (d == 0 || (rebind & 1))
                vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, 0, 1, &set, 0, NULL);
            if (d == 0 || (rebind & 2))
                vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof count, count);
            vkCmdDraw(cmd, 3, 1, 0, 0);
        }
        vkCmdEndRenderPass(cmd);
        CHECK(vkEndCommandBuffer(cmd));
        VkSubmitInfo submit = {VK_STRUCTURE_TYPE_SUBMIT_INFO, NULL, 0, NULL, NULL, 1, &cmd};
        CHECK(vkQueueSubmit(queue, 1, &submit, fence));
        CHECK(vkWaitForFences(dev, 1, &fence, VK_TRUE, UINT64_MAX));
        CHECK(vkResetFences(dev, 1, &fence));
    }
    long after = resident_kib();
    static const char *again[] = {"nothing", "the set", "the push constants", "the set and the push constants"};
    printf("%-22s %d draw%s a frame, %s again before each: resident %ld -> %ld KiB, %.1f KiB a frame\n", argv[1], draws,
           draws == 1 ? "" : "s", again[rebind & 3], before, after, (double)(after - before) / frames);
    vkDeviceWaitIdle(dev);
    return 0; /* the objects go with the process: only the frames' growth is measured */
}
