// Program cache: linked programs kept on disk as the driver's own binaries
// (glGetProgramBinary), so a scene compiled once shows its first frame at once on the next
// launch instead of after a link of up to seconds (issue 12: 0.9 s midi, 2.5 s character on NVIDIA).
//
//   unsigned id = LoadCachedProgram(text, path);       // 0: not cached, refused or corrupt
//   if (!id) { ...compile and link...; StoreCachedProgram(id, text, path); }
//
// Folder: $XDG_CACHE_HOME/sdfvj/programs, else ~/.cache/sdfvj/programs. One file per program,
// named by a hash of its key: the full program text (which holds the variant's #defines and,
// for the quick tier, its pragma), the render path, and the driver (GL_VENDOR, GL_RENDERER,
// GL_VERSION). The key is also written inside the file and compared on load, with a checksum of
// the binary: a file from another driver, a truncated or corrupt file, or a binary the driver
// refuses (glProgramBinary fails to link after a driver update) is deleted and the program is
// compiled as if there were no cache. Nothing here reports an error to the performer.
// Writes are atomic (a temp file renamed over the name): a crash never leaves half a file.
// The newest 400 programs are kept (SDFVJ_PROGRAM_CACHE_MAX_FILES), older ones deleted on a store.
// Off with SDFVJ_PROGRAM_CACHE=0 or `--no-program-cache`. GL calls: the calling thread's context.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "shader/shader.h"

namespace sdfvj {

// False when SDFVJ_PROGRAM_CACHE is "0" (or "off", "false").
bool ProgramCacheEnabled();
// The folder the files go to (created on the first store).
std::string ProgramCacheFolder();
// The driver part of the key: "GL_VENDOR | GL_RENDERER | GL_VERSION" of the current context,
// unless a test set another one (SetProgramCacheDriver("") goes back to the context's).
std::string ProgramCacheDriver();
void SetProgramCacheDriver(const std::string& driver);
// The file a program's binary is kept in (whether or not it exists).
std::string CachedProgramFile(const std::string& text, RenderPath path);
// A new linked program from the cache on the current context, or 0 (absent, refused, corrupt:
// the last two delete the file).
unsigned LoadCachedProgram(const std::string& text, RenderPath path);
// The cached binary of a program without loading it (no GL calls but the driver's name): for a
// loader thread (CompileWorker::SubmitLoad). False when absent or corrupt (then deleted).
bool ReadCachedBinary(const std::string& text, RenderPath path, unsigned* format, std::vector<uint8_t>* binary);
// Deletes a program's file (the driver refused its binary).
void ForgetCachedProgram(const std::string& text, RenderPath path);
// A new program from a binary on the current context (glProgramBinary), or 0 when the driver
// refuses it (its GL error is cleared).
unsigned LoadProgramBinary(unsigned format, const void* binary, size_t length);
// Stores a linked program's binary. False when the cache is off or the driver gives no binary
// (GL_PROGRAM_BINARY_LENGTH 0: Mesa with its own disk cache off) or the folder is not writable.
bool StoreCachedProgram(unsigned program, const std::string& text, RenderPath path);
// The same for a binary already read back (the compile worker's binary hand-over).
bool StoreCachedBinary(unsigned format, const std::vector<uint8_t>& binary, const std::string& text, RenderPath path);

}  // namespace sdfvj
