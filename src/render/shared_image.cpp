#include "render/shared_image.h"

#include <dlfcn.h>
#include <epoxy/gl.h>
#include <unistd.h>

#include <cstring>
#include <mutex>
#include <vector>

#if SDFVJ_VULKAN
#define VK_NO_PROTOTYPES
#include <vulkan/vulkan.h>
#endif

namespace sdfvj {

#if SDFVJ_VULKAN
namespace {

// The process's Vulkan device on the GL context's GPU: made once (instance and device cost tens of
// milliseconds, more on NVIDIA) and kept until the process ends; every image is allocated from it.
struct VkDeviceOnce {
    void* lib = nullptr;
    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice phys = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    PFN_vkCreateImage createImage = nullptr;
    PFN_vkDestroyImage destroyImage = nullptr;
    PFN_vkGetImageMemoryRequirements imageRequirements = nullptr;
    PFN_vkGetPhysicalDeviceMemoryProperties memoryProperties = nullptr;
    PFN_vkAllocateMemory allocateMemory = nullptr;
    PFN_vkFreeMemory freeMemory = nullptr;
    PFN_vkBindImageMemory bindImageMemory = nullptr;
    PFN_vkGetMemoryFdKHR getMemoryFd = nullptr;
    bool made = false;   // Make() succeeded (it is tried once)
    std::string why;   // why there is none

    bool Make() {
        if (!epoxy_has_gl_extension("GL_EXT_memory_object_fd")) {
            why = "this GL cannot import memory (no GL_EXT_memory_object_fd)";
            return false;
        }
        uint8_t glUuid[GL_UUID_SIZE_EXT] = {};
        glGetUnsignedBytei_vEXT(GL_DEVICE_UUID_EXT, 0, glUuid);
        lib = dlopen("libvulkan.so.1", RTLD_NOW | RTLD_LOCAL);
        if (!lib) {
            why = "no Vulkan loader (libvulkan.so.1)";
            return false;
        }
        auto gipa = (PFN_vkGetInstanceProcAddr)dlsym(lib, "vkGetInstanceProcAddr");
        auto createInstance = gipa ? (PFN_vkCreateInstance)gipa(VK_NULL_HANDLE, "vkCreateInstance") : nullptr;
        VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
        app.pApplicationName = "sdfvj";
        app.apiVersion = VK_API_VERSION_1_1;
        VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
        ici.pApplicationInfo = &app;
        if (!createInstance || createInstance(&ici, nullptr, &instance) != VK_SUCCESS) {
            why = "vkCreateInstance (Vulkan 1.1) failed: no Vulkan driver";
            return false;
        }
#define SDFVJ_VK(name) auto name = (PFN_##name)gipa(instance, #name)
        SDFVJ_VK(vkEnumeratePhysicalDevices);
        SDFVJ_VK(vkGetPhysicalDeviceProperties2);
        SDFVJ_VK(vkCreateDevice);
        SDFVJ_VK(vkGetDeviceProcAddr);
        memoryProperties = (PFN_vkGetPhysicalDeviceMemoryProperties)gipa(instance, "vkGetPhysicalDeviceMemoryProperties");
        uint32_t n = 0;
        vkEnumeratePhysicalDevices(instance, &n, nullptr);
        std::vector<VkPhysicalDevice> devices(n);
        vkEnumeratePhysicalDevices(instance, &n, devices.data());
        for (VkPhysicalDevice d : devices) {
            VkPhysicalDeviceIDProperties id{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ID_PROPERTIES};
            VkPhysicalDeviceProperties2 p{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
            p.pNext = &id;
            vkGetPhysicalDeviceProperties2(d, &p);
            if (std::memcmp(id.deviceUUID, glUuid, VK_UUID_SIZE) == 0) phys = d;
        }
        if (!phys) {
            why = "no Vulkan device has the GL device's UUID (of " + std::to_string(n) + ")";
            return false;
        }
        const float priority = 1.0f;
        VkDeviceQueueCreateInfo q{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
        q.queueCount = 1;
        q.pQueuePriorities = &priority;
        const char* exts[] = {VK_KHR_EXTERNAL_MEMORY_FD_EXTENSION_NAME};
        VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
        dci.queueCreateInfoCount = 1;
        dci.pQueueCreateInfos = &q;
        dci.enabledExtensionCount = 1;
        dci.ppEnabledExtensionNames = exts;
        if (vkCreateDevice(phys, &dci, nullptr, &device) != VK_SUCCESS) {
            why = "vkCreateDevice with VK_KHR_external_memory_fd failed";
            return false;
        }
#define SDFVJ_VKD(name) (PFN_##name)vkGetDeviceProcAddr(device, #name)
        createImage = SDFVJ_VKD(vkCreateImage);
        destroyImage = SDFVJ_VKD(vkDestroyImage);
        imageRequirements = SDFVJ_VKD(vkGetImageMemoryRequirements);
        allocateMemory = SDFVJ_VKD(vkAllocateMemory);
        freeMemory = SDFVJ_VKD(vkFreeMemory);
        bindImageMemory = SDFVJ_VKD(vkBindImageMemory);
        getMemoryFd = SDFVJ_VKD(vkGetMemoryFdKHR);
#undef SDFVJ_VK
#undef SDFVJ_VKD
        return true;
    }
};

std::mutex g_vkMutex;
VkDeviceOnce* g_vk = nullptr;   // never freed: images may outlive any owner but the process

// The device, made on the first call (GL context current); null with why.
VkDeviceOnce* Device(std::string* why) {
    std::lock_guard<std::mutex> lock(g_vkMutex);
    if (!g_vk) {
        g_vk = new VkDeviceOnce;
        g_vk->made = g_vk->Make();
    }
    if (!g_vk->made) {
        *why = g_vk->why;
        return nullptr;
    }
    return g_vk;
}

}  // namespace

struct SharedImage::Vk {
    VkDeviceOnce* d = nullptr;
    VkImage image = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    ~Vk() {
        if (image) d->destroyImage(d->device, image, nullptr);
        if (memory) d->freeMemory(d->device, memory, nullptr);
    }
};
#else
struct SharedImage::Vk {};
#endif

SharedImage::SharedImage() = default;
SharedImage::~SharedImage() = default;

bool SharedImage::Prepare(std::string* why) {
#if !SDFVJ_VULKAN
    *why = "built without the Vulkan headers (libvulkan-dev)";
    return false;
#else
    return Device(why) != nullptr;
#endif
}

bool SharedImage::Create(int width, int height, std::string* why) {
#if !SDFVJ_VULKAN
    (void)width, (void)height;
    *why = "built without the Vulkan headers (libvulkan-dev)";
    return false;
#else
    VkDeviceOnce* d = Device(why);
    if (!d) return false;
    vk_ = std::make_unique<Vk>();
    Vk& v = *vk_;
    v.d = d;
    VkExternalMemoryImageCreateInfo ext{VK_STRUCTURE_TYPE_EXTERNAL_MEMORY_IMAGE_CREATE_INFO};
    ext.handleTypes = VK_EXTERNAL_MEMORY_HANDLE_TYPE_OPAQUE_FD_BIT;
    VkImageCreateInfo img{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    img.pNext = &ext;
    img.imageType = VK_IMAGE_TYPE_2D;
    img.format = VK_FORMAT_R8G8B8A8_UNORM;
    img.extent = {(uint32_t)width, (uint32_t)height, 1};
    img.mipLevels = 1;
    img.arrayLayers = 1;
    img.samples = VK_SAMPLE_COUNT_1_BIT;
    img.tiling = VK_IMAGE_TILING_OPTIMAL;
    img.usage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
    img.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    if (d->createImage(d->device, &img, nullptr, &v.image) != VK_SUCCESS) {
        *why = "vkCreateImage of an exportable RGBA8 image failed";
        return false;
    }
    VkMemoryRequirements req{};
    d->imageRequirements(d->device, v.image, &req);
    VkPhysicalDeviceMemoryProperties mp{};
    d->memoryProperties(d->phys, &mp);
    uint32_t type = UINT32_MAX;
    for (uint32_t i = 0; i < mp.memoryTypeCount && type == UINT32_MAX; ++i)
        if ((req.memoryTypeBits & (1u << i)) && (mp.memoryTypes[i].propertyFlags & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT)) type = i;
    for (uint32_t i = 0; i < mp.memoryTypeCount && type == UINT32_MAX; ++i)
        if (req.memoryTypeBits & (1u << i)) type = i;
    VkMemoryDedicatedAllocateInfo dedicated{VK_STRUCTURE_TYPE_MEMORY_DEDICATED_ALLOCATE_INFO};
    dedicated.image = v.image;
    VkExportMemoryAllocateInfo exportInfo{VK_STRUCTURE_TYPE_EXPORT_MEMORY_ALLOCATE_INFO};
    exportInfo.pNext = &dedicated;
    exportInfo.handleTypes = VK_EXTERNAL_MEMORY_HANDLE_TYPE_OPAQUE_FD_BIT;
    VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    ai.pNext = &exportInfo;
    ai.allocationSize = req.size;
    ai.memoryTypeIndex = type;
    if (type == UINT32_MAX || d->allocateMemory(d->device, &ai, nullptr, &v.memory) != VK_SUCCESS ||
        d->bindImageMemory(d->device, v.image, v.memory, 0) != VK_SUCCESS) {
        *why = "cannot allocate exportable memory for the image";
        return false;
    }
    size_ = req.size;
    return true;
#endif
}

int SharedImage::ExportFd() {
#if SDFVJ_VULKAN
    if (!vk_ || !vk_->memory) return -1;
    VkMemoryGetFdInfoKHR info{VK_STRUCTURE_TYPE_MEMORY_GET_FD_INFO_KHR};
    info.memory = vk_->memory;
    info.handleType = VK_EXTERNAL_MEMORY_HANDLE_TYPE_OPAQUE_FD_BIT;
    int fd = -1;
    if (vk_->d->getMemoryFd(vk_->d->device, &info, &fd) != VK_SUCCESS) return -1;
    return fd;
#else
    return -1;
#endif
}

unsigned ImportSharedTexture(int fd, uint64_t size, int width, int height, unsigned* memory, std::string* why) {
    *memory = 0;
    if (!epoxy_has_gl_extension("GL_EXT_memory_object_fd")) {
        ::close(fd);
        *why = "this GL cannot import memory (no GL_EXT_memory_object_fd)";
        return 0;
    }
    while (glGetError() != GL_NO_ERROR) {}
    GLuint mem = 0, tex = 0;
    glCreateMemoryObjectsEXT(1, &mem);
    const GLint dedicated = GL_TRUE;
    glMemoryObjectParameterivEXT(mem, GL_DEDICATED_MEMORY_OBJECT_EXT, &dedicated);
    glImportMemoryFdEXT(mem, size, GL_HANDLE_TYPE_OPAQUE_FD_EXT, fd);   // GL owns the fd now
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_TILING_EXT, GL_OPTIMAL_TILING_EXT);
    glTexStorageMem2DEXT(GL_TEXTURE_2D, 1, GL_RGBA8, width, height, mem, 0);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    const GLenum err = glGetError();
    if (err != GL_NO_ERROR) {
        glDeleteTextures(1, &tex);
        glDeleteMemoryObjectsEXT(1, &mem);
        *why = "GL refused the imported memory (GL error " + std::to_string(err) + ")";
        return 0;
    }
    *memory = mem;
    return tex;
}

}  // namespace sdfvj
