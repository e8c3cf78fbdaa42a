#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <string>

#include <glm/glm.hpp>

#include "render/gl_stages.h"
#include "render/gpu_timer.h"
#include "render/kept_sizes.h"
#include "render/render.h"

namespace sdfvj {

namespace {
constexpr int kConeTile = 8;   // main_comp.glsl's CONE_TILE
// main_comp.glsl's QuadDeferred (a head of 8 uints) and QuadDeferredEntries (4 uvec4 an entry)
constexpr GLuint kDeferHeadBinding = 3, kDeferEntriesBinding = 4;
constexpr long long kDeferEntryBytes = 64;
}

FrameRenderer::~FrameRenderer() { Release(); }

void FrameRenderer::ReleaseTarget(Target& t) {
    if (t.fbo) glDeleteFramebuffers(1, &t.fbo);
    if (t.texture) glDeleteTextures(1, &t.texture);
    if (t.cone) glDeleteTextures(1, &t.cone);
    t = Target{};
}

void FrameRenderer::Release() {
    Target t = Current();
    ReleaseTarget(t);
    for (Target& k : kept_) ReleaseTarget(k);
    kept_.clear();
    if (vao_) glDeleteVertexArrays(1, &vao_);
    if (query_) glDeleteQueries(1, &query_);
    if (stateBuffer_) glDeleteBuffers(1, &stateBuffer_);
    if (quadTexture_) glDeleteTextures(1, &quadTexture_);
    if (deferBuffer_) glDeleteBuffers(1, &deferBuffer_);
    if (deferHead_) glDeleteBuffers(1, &deferHead_);
    fbo_ = texture_ = vao_ = query_ = coneTexture_ = stateBuffer_ = quadTexture_ = deferBuffer_ = deferHead_ = 0;
    quadW_ = quadH_ = 0;
    deferRoom_ = deferFailed_ = 0;
    width_ = height_ = 0;
}

void FrameRenderer::SetKeptSizes(int n) {
    keepSizes_ = (size_t)std::max(n, 0);
    while (kept_.size() > keepSizes_) {
        ReleaseTarget(kept_.front());
        kept_.erase(kept_.begin());
    }
}

bool FrameRenderer::Resize(int width, int height, std::string* error, bool floatTarget) {
    if (width == width_ && height == height_ && floatTarget == floatTarget_ && fbo_) return true;
    GLint maxSize = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
    if (width <= 0 || height <= 0 || width > maxSize || height > maxSize) {
        *error = "frame size " + std::to_string(width) + "x" + std::to_string(height) + " is not supported (1.." +
                 std::to_string(maxSize) + " per side)";
        return false;
    }
    const Target next = SwapKeptSize(kept_, keepSizes_, Current(), width, height, floatTarget, ReleaseTarget);
    fbo_ = next.fbo, texture_ = next.texture, coneTexture_ = next.cone;
    width_ = next.w, height_ = next.h, floatTarget_ = next.isFloat;
    if (!vao_) glGenVertexArrays(1, &vao_);
    if (!query_) glGenQueries(1, &query_);
    if (!stateBuffer_) stateBuffer_ = CreateSceneStateBuffer();
    if (fbo_) return true;
    glGenTextures(1, &texture_);
    glBindTexture(GL_TEXTURE_2D, texture_);
    glTexStorage2D(GL_TEXTURE_2D, 1, floatTarget ? GL_RGBA32F : GL_RGBA8, width, height);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glGenFramebuffers(1, &fbo_);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture_, 0);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        *error = "offscreen framebuffer is incomplete";
        Target t = Current();
        ReleaseTarget(t);
        fbo_ = texture_ = coneTexture_ = 0;
        return false;
    }
    glGenTextures(1, &coneTexture_);
    glBindTexture(GL_TEXTURE_2D, coneTexture_);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_R32F, (width + kConeTile - 1) / kConeTile, (height + kConeTile - 1) / kConeTile);
    width_ = width;
    height_ = height;
    floatTarget_ = floatTarget;
    ++targetsMade_;
    return true;
}

CameraBasis MakeCameraBasis(const Vec3f& pos, const Vec3f& target, float fovDegrees, int height) {
    // render.glsl cameraRay, in float as the GPU computes it: forward, the screen's right and up.
    const glm::vec3 toTarget = glm::vec3(target[0], target[1], target[2]) - glm::vec3(pos[0], pos[1], pos[2]);
    const float len = glm::length(toTarget);
    const glm::vec3 forward = len > 1e-20f ? toTarget / len : glm::vec3(0.0f, 1.0f, 0.0f);   // safeNormalize
    const glm::vec3 up = std::fabs(forward.y) > 0.999f ? glm::vec3(0.0f, 0.0f, 1.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
    const glm::vec3 side = glm::cross(up, forward);
    const glm::vec3 right = side / glm::length(side);   // divided, as before (not glm::normalize's reciprocal)
    const glm::vec3 camUp = glm::cross(forward, right);
    const float tanHalf = std::tan(glm::radians(std::clamp(fovDegrees, 1.0f, 179.0f)) * 0.5f);
    const float perPixel = 2.0f * tanHalf / std::max((float)height, 1.0f);
    const glm::vec3 dx = right * perPixel, dy = camUp * perPixel;
    return CameraBasis{{forward.x, forward.y, forward.z}, {dx.x, dx.y, dx.z}, {dy.x, dy.y, dy.z}, perPixel};
}

unsigned CreateSceneStateBuffer() {
    GLuint buffer = 0;
    glGenBuffers(1, &buffer);
    glBindBuffer(GL_UNIFORM_BUFFER, buffer);
    glBufferStorage(GL_UNIFORM_BUFFER, kSceneStateBytes, nullptr, 0);
    glBindBuffer(GL_UNIFORM_BUFFER, 0);
    return buffer;
}

void BindSceneStateBuffer(unsigned buffer) {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kSceneStateBinding, buffer);   // the setup stores it
    glBindBufferBase(GL_UNIFORM_BUFFER, kSceneStateBinding, buffer);          // the frame reads it
}

Vec3f OrbitCamera(const SceneInfo& scene, float yaw, float pitch) {
    if (yaw == 0.0f && pitch == 0.0f) return scene.camPos;
    const double ox = scene.camPos[0] - scene.camTarget[0], oy = scene.camPos[1] - scene.camTarget[1],
                 oz = scene.camPos[2] - scene.camTarget[2];
    const double dist = std::sqrt(ox * ox + oy * oy + oz * oz);
    if (dist <= 0.0) return scene.camPos;
    const double limit = 1.5;   // about 86 degrees: never over the pole, where "up" flips
    const double elevation = std::clamp(std::asin(std::clamp(oy / dist, -1.0, 1.0)) + pitch, -limit, limit);
    const double azimuth = std::atan2(ox, oz) + yaw;
    const double flat = dist * std::cos(elevation);
    return {float(scene.camTarget[0] + flat * std::sin(azimuth)), float(scene.camTarget[1] + dist * std::sin(elevation)),
            float(scene.camTarget[2] + flat * std::cos(azimuth))};
}

void FrameRenderer::Draw(const Program& program, const SceneInfo& scene, const FrameInputs& in, bool timeGpu) {
    if (!program.IsValid() || !fbo_) return;   // a program that failed to build just skips its draws
    const Program& p = program;
    p.Set("u_time", (float)in.time);
    p.Set("u_frame", (float)in.frame);
    p.Set("u_beat", in.beat);
    p.Set("u_bpm", in.bpm);
    p.Set("u_resolution", (float)width_, (float)height_);
    const Vec3f cam = OrbitCamera(scene, in.orbitYaw, in.orbitPitch);
    p.Set("u_camPos", cam[0], cam[1], cam[2]);
    p.Set("u_camTarget", scene.camTarget[0], scene.camTarget[1], scene.camTarget[2]);
    p.Set("u_fov", scene.fov);
    {   // render.glsl cameraRay's basis, once for the frame (uniforms.glsl CAMERA_UNIFORMS)
        const CameraBasis b = MakeCameraBasis(cam, scene.camTarget, scene.fov, height_);
        p.Set("u_camForward", b.forward[0], b.forward[1], b.forward[2]);
        p.Set("u_camDX", b.dx[0], b.dx[1], b.dx[2]);
        p.Set("u_camDY", b.dy[0], b.dy[1], b.dy[2]);
        p.Set("u_pixelAngle", b.pixelAngle);
    }
    p.Set("u_lightDir", scene.lightDir[0], scene.lightDir[1], scene.lightDir[2]);
    p.Set("u_lightColor", scene.lightColor[0], scene.lightColor[1], scene.lightColor[2]);
    p.Set("u_roughness", scene.roughness);
    p.Set("u_metalness", scene.metalness);
    const Quality& q = in.quality;
    p.Set("u_maxSteps", (float)q.maxSteps);
    p.Set("u_hitEps", q.hitEps);
    p.Set("u_maxDist", q.maxDist);
    p.Set("u_stepFactor", q.stepFactor);
    p.Set("u_fixedStep", q.fixedStep);
    p.Set("u_shadowSteps", (float)q.shadowSteps);
    p.Set("u_shadowK", q.shadowK);
    p.Set("u_aoSamples", (float)q.aoSamples);
    p.Set("u_normalEps", q.normalEps);
    p.Set("u_effectsOff", (float)in.effectsOff);
    if (!p.Literals().empty()) p.SetFloats("u_lit", p.Literals());
    p.BindEvaluator();   // an evaluator program's code (shader/evaluator.h), where it has one
    for (const ParamDecl& d : scene.params) {
        float v = d.defaultValue;
        for (const auto& [name, value] : in.params)
            if (name == d.name) v = ClampParam(d, value);   // never unclamped into the shader
        p.Set("u_" + d.name, v);
    }

    const bool wallClock = timeGpu && IsSoftwareRenderer();
    const auto wallStart = std::chrono::steady_clock::now();
    if (timeGpu && !wallClock) glBeginQuery(GL_TIME_ELAPSED, query_);
    glUseProgram(p.Id());
    if (p.Path() == RenderPath::Compute) {
        glBindImageTexture(0, texture_, 0, GL_FALSE, 0, GL_WRITE_ONLY, floatTarget_ ? GL_RGBA32F : GL_RGBA8);
        glBindImageTexture(1, coneTexture_, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32F);
        const GLuint gx = (GLuint)std::max(p.GroupX(), 1), gy = (GLuint)std::max(p.GroupY(), 1);
        if (p.FrameState()) {   // the scene's setup once for the frame: the pre-pass stores it, or a group of its own
            BindSceneStateBuffer(stateBuffer_);
            if (!q.conePrepass) {
                p.Set("u_conePass", 3.0f);
                glDispatchCompute(1, 1, 1);
                glMemoryBarrier(GL_UNIFORM_BARRIER_BIT);
            }
        }
        if (q.conePrepass) {   // one invocation per 8x8 tile, in the program's groups
            p.Set("u_conePass", 1.0f);
            const GLuint tilesX = (GLuint)(width_ + kConeTile - 1) / kConeTile, tilesY = (GLuint)(height_ + kConeTile - 1) / kConeTile;
            glDispatchCompute((tilesX + gx - 1) / gx, (tilesY + gy - 1) / gy, 1);
            glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_UNIFORM_BARRIER_BIT);
        }
        if (p.QuadReflections()) {   // the bounce once per 2x2 pixels, before the frame reads it
            const int qw = (width_ + 1) / 2, qh = (height_ + 1) / 2;
            if (qw != quadW_ || qh != quadH_) {
                if (quadTexture_) glDeleteTextures(1, &quadTexture_);
                glGenTextures(1, &quadTexture_);
                glBindTexture(GL_TEXTURE_2D, quadTexture_);
                glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32UI, qw, qh);
                quadW_ = qw, quadH_ = qh;
            }
            glBindImageTexture(2, quadTexture_, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32UI);
            p.Set("u_conePass", q.conePrepass ? 4.0f : 5.0f);
            p.Set("u_rowOffset", 0.0f);
            glDispatchCompute(((GLuint)qw + gx - 1) / gx, ((GLuint)qh + gy - 1) / gy, 1);
            glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        }
        if (p.QuadDefer()) {   // the list of bounces left to their own dispatch, emptied (main_comp.glsl QuadDeferred)
            const long long room = QuadDeferRoom();
            const GLuint head[8] = {0u, 1u, 1u, 0u, (GLuint)std::min(room, (long long)UINT32_MAX), 0u, 0u, 0u};
            glBindBuffer(GL_SHADER_STORAGE_BUFFER, deferHead_);
            glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof head, head);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kDeferHeadBinding, deferHead_);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kDeferEntriesBinding, deferBuffer_);
        }
        p.Set("u_conePass", q.conePrepass ? 2.0f : 0.0f);
        // Strips of whole work-groups (main_comp.glsl adds u_rowOffset to each invocation's row).
        const GLuint rows = (GLuint)height_, perStrip = ((rows + (GLuint)strips_ - 1) / (GLuint)strips_ + gy - 1) / gy * gy;
        for (GLuint y0 = 0; y0 < rows; y0 += perStrip) {
            p.Set("u_rowOffset", (float)y0);
            glDispatchCompute(((GLuint)width_ + gx - 1) / gx, (std::min(perStrip, rows - y0) + gy - 1) / gy, 1);
            if (strips_ > 1) glFinish();
        }
        if (p.QuadDefer()) {   // the listed bounces, one an invocation, as many groups as the frame listed
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
            p.Set("u_conePass", 6.0f);
            glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, deferHead_);
            glDispatchComputeIndirect(0);
            glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
        }
        glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    } else {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
        glViewport(0, 0, width_, height_);
        glDisable(GL_DEPTH_TEST);
        SetOverwriteBlend();
        glBindVertexArray(vao_);
        glDrawArrays(GL_TRIANGLES, 0, 3);
    }
    if (wallClock) {
        glFinish();
        lastGpuMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wallStart).count();
    } else if (timeGpu) {
        glEndQuery(GL_TIME_ELAPSED);
        GLuint64 ns = 0;
        glGetQueryObjectui64v(query_, GL_QUERY_RESULT, &ns);
        lastGpuMs_ = (double)ns * 1e-6;
    }
}

long long FrameRenderer::QuadDeferRoom() {
    const long long room = deferRoomAsked_ >= 0 ? deferRoomAsked_ : (long long)width_ * height_ / 8;
    if (!deferHead_) {
        glGenBuffers(1, &deferHead_);
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, deferHead_);
        glBufferStorage(GL_SHADER_STORAGE_BUFFER, 32, nullptr, GL_DYNAMIC_STORAGE_BIT);
    }
    // The entries: immutable, no CPU access (the GPU's own memory); grown, never shrunk, and not
    // asked again for a size the driver had no memory for.
    if (deferBuffer_ && (room <= deferRoom_ || (deferFailed_ != 0 && room >= deferFailed_))) return std::min(room, deferRoom_);
    auto remake = [this](GLsizeiptr bytes) {   // the size the driver gave it
        if (deferBuffer_) glDeleteBuffers(1, &deferBuffer_);
        glGenBuffers(1, &deferBuffer_);
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, deferBuffer_);
        glBufferStorage(GL_SHADER_STORAGE_BUFFER, bytes, nullptr, 0);
        GLint64 got = 0;
        glGetBufferParameteri64v(GL_SHADER_STORAGE_BUFFER, GL_BUFFER_SIZE, &got);
        return got;
    };
    const GLsizeiptr want = (GLsizeiptr)(std::max(room, 1LL) * kDeferEntryBytes);
    if (remake(want) >= want) {
        deferRoom_ = room;
        return room;
    }
    // No memory for it: a list of one entry with room for none, every pixel's bounce traced in the frame.
    while (glGetError() != GL_NO_ERROR) {}   // its GL_OUT_OF_MEMORY, not a later check's
    remake(kDeferEntryBytes);
    deferRoom_ = 0;
    deferFailed_ = room;
    return 0;
}

long long FrameRenderer::LastQuadDeferred() const {
    if (!deferHead_) return 0;
    GLuint count = 0;
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, deferHead_);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 12, sizeof count, &count);
    return count;
}

GpuTimerRing::~GpuTimerRing() {
    if (!ids_.empty()) glDeleteQueries((GLsizei)ids_.size(), ids_.data());
}

bool GpuTimerRing::Begin(int tag) {
    if (open_ || count_ == slots_) {
        ++refused_;
        return false;
    }
    if (ids_.empty()) {
        ids_.resize((size_t)slots_);
        tags_.resize((size_t)slots_);
        glGenQueries(slots_, ids_.data());
    }
    const int slot = (head_ + count_) % slots_;
    tags_[(size_t)slot] = tag;
    glBeginQuery(GL_TIME_ELAPSED, ids_[(size_t)slot]);
    ++count_;
    open_ = true;
    return true;
}

void GpuTimerRing::End() {
    if (!open_) return;
    glEndQuery(GL_TIME_ELAPSED);
    open_ = false;
}

std::vector<GpuTimerRing::Sample> GpuTimerRing::Poll() {
    std::vector<Sample> done;
    // Results arrive in order: stop at the first that is not there yet (the open one never is).
    while (count_ > (open_ ? 1 : 0)) {
        const GLuint id = ids_[(size_t)head_];
        GLint available = 0;
        glGetQueryObjectiv(id, GL_QUERY_RESULT_AVAILABLE, &available);
        if (!available) break;
        GLuint64 ns = 0;
        glGetQueryObjectui64v(id, GL_QUERY_RESULT, &ns);   // available: this does not wait
        done.push_back({tags_[(size_t)head_], (double)ns * 1e-6});
        head_ = (head_ + 1) % slots_;
        --count_;
    }
    return done;
}

std::vector<uint8_t> FrameRenderer::ReadPixels() const {
    std::vector<uint8_t> rgba((size_t)width_ * height_ * 4);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    // GL's first row is the bottom one; images want the top first.
    const size_t row = (size_t)width_ * 4;
    std::vector<uint8_t> tmp(row);
    for (int y = 0; y < height_ / 2; ++y) {
        uint8_t* a = rgba.data() + row * y;
        uint8_t* b = rgba.data() + row * (height_ - 1 - y);
        std::memcpy(tmp.data(), a, row);
        std::memcpy(a, b, row);
        std::memcpy(b, tmp.data(), row);
    }
    return rgba;
}

std::vector<float> FrameRenderer::ReadPixelsFloat() const {
    std::vector<float> rgba((size_t)width_ * height_ * 4);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_FLOAT, rgba.data());
    return rgba;
}

std::string GlRendererName() {
    const GLubyte* s = glGetString(GL_RENDERER);
    return s ? (const char*)s : "unknown";
}

bool PreferCompileThread() {
    const GLubyte* v = glGetString(GL_VERSION);
    return IsSoftwareRenderer() || (v && std::string((const char*)v).find("Mesa") != std::string::npos);
}

bool IsSoftwareRenderer() {
    std::string r = GlRendererName();
    return r.find("llvmpipe") != std::string::npos || r.find("softpipe") != std::string::npos;
}

double MedianMs(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace sdfvj
