// SharedImage: an RGBA8 image in memory two processes' GL contexts can both bind as a texture
// (issue 12: a render process's frames shown by the show's process without a copy).
//
// GL can import memory (GL_EXT_memory_object_fd) but not allocate it for export, so the image is
// allocated through Vulkan (VK_KHR_external_memory_fd, an opaque fd) on the device whose UUID is
// the GL context's, and each process imports an fd of it as a texture. The Vulkan loader is opened
// at run time (dlopen libvulkan.so.1): a machine without it only loses this transport, with the
// reason. Vulkan never touches the image after it is made; GL reads and writes it.
#pragma once
#include <cstdint>
#include <memory>
#include <string>

namespace sdfvj {

class SharedImage {
public:
    SharedImage();
    ~SharedImage();   // frees the image (GL textures of it must be gone); the device stays
    SharedImage(const SharedImage&) = delete;
    SharedImage& operator=(const SharedImage&) = delete;
    // The process's Vulkan device on the current GL context's GPU, made now (once per process: every
    // image is allocated from it), so that a later Create costs only the image. False with why.
    static bool Prepare(std::string* why);
    // Allocates width x height RGBA8 on the Vulkan device of the current GL context. False with why.
    bool Create(int width, int height, std::string* why);
    // A new fd of the image's memory (each import takes one); -1 on failure.
    int ExportFd();
    uint64_t Size() const { return size_; }

private:
    struct Vk;
    std::unique_ptr<Vk> vk_;
    uint64_t size_ = 0;
};

// Imports `fd` (taken, closed on failure too) holding `size` bytes as a width x height RGBA8 texture
// of the current GL context. Returns the texture (and its memory object in *memory), or 0 with why.
unsigned ImportSharedTexture(int fd, uint64_t size, int width, int height, unsigned* memory, std::string* why);

}  // namespace sdfvj
