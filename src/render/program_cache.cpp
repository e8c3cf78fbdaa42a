#include "render/program_cache.h"

#include <epoxy/gl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>
#include <vector>

namespace fs = std::filesystem;

namespace sdfvj {

namespace {

// File layout: magic, version, binary format, key length, key (driver, path, full program text),
// binary length, FNV-1a of the binary, binary. Everything is checked on load.
constexpr char kMagic[8] = {'S', 'D', 'F', 'V', 'J', 'P', 'R', 'G'};
constexpr uint32_t kVersion = 1;

std::mutex g_driverMutex;   // the override is set by tests on the render thread, read by the compile worker
std::string g_driverOverride;

std::string Key(const std::string& text, RenderPath path) {
    return ProgramCacheDriver() + "\n" + RenderPathName(path) + "\n" + text;
}

std::string Hex(uint64_t v) {
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", (unsigned long long)v);
    return buf;
}

template <typename T>
void Put(std::string* out, T v) {
    out->append(reinterpret_cast<const char*>(&v), sizeof v);
}

template <typename T>
bool Get(const std::string& in, size_t* at, T* v) {
    if (in.size() < *at + sizeof(T)) return false;
    std::memcpy(v, in.data() + *at, sizeof(T));
    *at += sizeof(T);
    return true;
}

// Keeps the folder to the newest kMaxFiles programs (SDFVJ_PROGRAM_CACHE_MAX_FILES overrides):
// a live-coding session stores one program per save, and nothing else ever deletes them.
// Loads touch their file, so "newest" means most recently used.
void Evict(const fs::path& folder) {
    size_t maxFiles = 400;
    if (const char* v = std::getenv("SDFVJ_PROGRAM_CACHE_MAX_FILES")) maxFiles = (size_t)std::max(1L, std::atol(v));
    std::vector<std::pair<fs::file_time_type, fs::path>> files;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(folder, ec))
        if (e.path().extension() == ".bin") files.emplace_back(e.last_write_time(ec), e.path());
    if (files.size() <= maxFiles) return;
    std::sort(files.begin(), files.end());
    for (size_t i = 0; i + maxFiles < files.size(); ++i) fs::remove(files[i].second, ec);
}

}  // namespace

bool ProgramCacheEnabled() {
    const char* v = std::getenv("SDFVJ_PROGRAM_CACHE");
    if (!v) return true;
    const std::string s = v;
    return !(s == "0" || s == "off" || s == "false" || s == "no");
}

std::string ProgramCacheFolder() {
    const char* xdg = std::getenv("XDG_CACHE_HOME");
    if (xdg && *xdg) return (fs::path(xdg) / "sdfvj" / "programs").string();
    const char* home = std::getenv("HOME");
    return (fs::path(home && *home ? home : "/tmp") / ".cache" / "sdfvj" / "programs").string();
}

std::string ProgramCacheDriver() {
    {
        std::lock_guard<std::mutex> lock(g_driverMutex);
        if (!g_driverOverride.empty()) return g_driverOverride;
    }
    auto str = [](GLenum name) {
        const GLubyte* s = glGetString(name);
        return s ? std::string((const char*)s) : std::string("unknown");
    };
    return str(GL_VENDOR) + " | " + str(GL_RENDERER) + " | " + str(GL_VERSION);
}

void SetProgramCacheDriver(const std::string& driver) {
    std::lock_guard<std::mutex> lock(g_driverMutex);
    g_driverOverride = driver;
}

std::string CachedProgramFile(const std::string& text, RenderPath path) {
    return (fs::path(ProgramCacheFolder()) / (Hex(HashBytes(Key(text, path))) + ".bin")).string();
}

bool ReadCachedBinary(const std::string& text, RenderPath path, unsigned* formatOut, std::vector<uint8_t>* binaryOut) {
    if (!ProgramCacheEnabled()) return false;
    const std::string key = Key(text, path);
    const std::string file = (fs::path(ProgramCacheFolder()) / (Hex(HashBytes(key)) + ".bin")).string();
    std::string bytes;
    {
        std::ifstream in(file, std::ios::binary);
        if (!in) return false;   // not cached: the common case, silent
        bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    auto refuse = [&] {
        std::error_code ec;
        fs::remove(file, ec);   // corrupt or another driver's: compile and store anew
        return false;
    };
    size_t at = 0;
    if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0) return refuse();
    at = sizeof kMagic;
    uint32_t version = 0, format = 0, keyLength = 0;
    uint64_t binaryLength = 0, checksum = 0;
    if (!Get(bytes, &at, &version) || version != kVersion || !Get(bytes, &at, &format) || !Get(bytes, &at, &keyLength))
        return refuse();
    if (bytes.size() < at + keyLength || bytes.compare(at, keyLength, key) != 0) return refuse();
    at += keyLength;
    if (!Get(bytes, &at, &binaryLength) || !Get(bytes, &at, &checksum) || bytes.size() != at + binaryLength ||
        binaryLength == 0 || binaryLength > 0x7fffffffu)
        return refuse();
    const std::string binary = bytes.substr(at);
    if (HashBytes(binary) != checksum) return refuse();
    *formatOut = format;
    binaryOut->assign(binary.begin(), binary.end());
    std::error_code ec;
    fs::last_write_time(file, fs::file_time_type::clock::now(), ec);   // recently used: evicted last
    return true;
}

void ForgetCachedProgram(const std::string& text, RenderPath path) {
    std::error_code ec;
    fs::remove(CachedProgramFile(text, path), ec);
}

unsigned LoadProgramBinary(unsigned format, const void* binary, size_t length) {
    GLuint prog = glCreateProgram();
    glProgramBinary(prog, (GLenum)format, binary, (GLsizei)length);
    GLint linked = 0;
    glGetProgramiv(prog, GL_LINK_STATUS, &linked);
    if (!linked) {
        glDeleteProgram(prog);
        while (glGetError() != GL_NO_ERROR) {}   // GL_INVALID_ENUM for an unknown format is expected here
        return 0;
    }
    return prog;
}

unsigned LoadCachedProgram(const std::string& text, RenderPath path) {
    unsigned format = 0;
    std::vector<uint8_t> binary;
    if (!ReadCachedBinary(text, path, &format, &binary)) return 0;
    const unsigned prog = LoadProgramBinary(format, binary.data(), binary.size());
    if (!prog) ForgetCachedProgram(text, path);   // refused (a driver update): compile and store anew
    return prog;
}

bool StoreCachedProgram(unsigned program, const std::string& text, RenderPath path) {
    if (!ProgramCacheEnabled() || !program) return false;
    GLint length = 0;
    glGetProgramiv(program, GL_PROGRAM_BINARY_LENGTH, &length);
    if (length <= 0) return false;
    std::vector<uint8_t> binary((size_t)length);
    GLsizei got = 0;
    GLenum format = 0;
    glGetProgramBinary(program, length, &got, &format, binary.data());
    if (got <= 0) return false;
    binary.resize((size_t)got);
    return StoreCachedBinary(format, binary, text, path);
}

bool StoreCachedBinary(unsigned format, const std::vector<uint8_t>& binaryBytes, const std::string& text, RenderPath path) {
    if (!ProgramCacheEnabled() || binaryBytes.empty()) return false;
    const std::string binary(binaryBytes.begin(), binaryBytes.end());
    const std::string key = Key(text, path);
    std::string bytes(kMagic, sizeof kMagic);
    Put(&bytes, kVersion);
    Put(&bytes, (uint32_t)format);
    Put(&bytes, (uint32_t)key.size());
    bytes += key;
    Put(&bytes, (uint64_t)binary.size());
    Put(&bytes, HashBytes(binary));
    bytes += binary;
    std::error_code ec;
    const fs::path folder = ProgramCacheFolder();
    fs::create_directories(folder, ec);
    if (ec) return false;
    const fs::path file = folder / (Hex(HashBytes(key)) + ".bin");
    // A name of our own for the temp file: two sdfvj processes (or the worker and the render
    // thread) may store the same program at once; the last rename wins, both files are whole.
    static std::atomic<unsigned> serial{0};
    const fs::path tmp = folder / (file.filename().string() + ".tmp" + std::to_string(::getpid()) + "-" +
                                   std::to_string(serial.fetch_add(1)));
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        out.write(bytes.data(), (std::streamsize)bytes.size());
        if (!out) {
            fs::remove(tmp, ec);
            return false;
        }
    }
    fs::rename(tmp, file, ec);
    if (ec) {
        fs::remove(tmp, ec);
        return false;
    }
    Evict(folder);
    return true;
}

}  // namespace sdfvj
