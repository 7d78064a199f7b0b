// Model files from untrusted sources: load_model in a child process with memory and time limits,
// so that a parser that crashes, spins or allocates without bound ends in an error, not in the
// caller's process going down.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "clraster/clraster.hpp"
#include "io/model_loader.hpp"

namespace clraster::io {

// The default limits of a load: the loader's memory grows with the file (assimp's scenes take some
// 10 to 40 times a file's size, and our triangle list more), its time with the file's size too.
inline constexpr std::size_t kLoadMemoryFloor = std::size_t{1} << 30;  // 1 GiB
inline constexpr std::size_t kLoadMemoryPerFileByte = 64;
inline constexpr std::chrono::seconds kLoadTimeFloor{20};
inline constexpr std::chrono::seconds kLoadTimePerMiB{1};

// AddressSanitizer reserves terabytes of shadow memory, which no address-space limit leaves room
// for: in such builds the memory limit is not applied.
#if defined(__SANITIZE_ADDRESS__)
#define CLRASTER_ADDRESS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define CLRASTER_ADDRESS_SANITIZER 1
#endif
#endif
#ifdef CLRASTER_ADDRESS_SANITIZER
inline constexpr bool kBuiltWithAddressSanitizer = true;
#else
inline constexpr bool kBuiltWithAddressSanitizer = false;
#endif

struct ModelLoadLimits {
  // What the loading process may allocate beyond what the caller's process had; unset: the
  // default, max(kLoadMemoryFloor, kLoadMemoryPerFileByte * the file's size).
  std::optional<std::size_t> memory_bytes;
  // Wall-clock time; unset: the default, max(kLoadTimeFloor, kLoadTimePerMiB * the file's size).
  std::optional<std::chrono::milliseconds> time;
};

// The limits a load of a file of `file_bytes` bytes runs with: `requested`'s, the defaults for the rest.
struct ResolvedLoadLimits {
  std::size_t memory_bytes;
  std::chrono::milliseconds time;
};
ResolvedLoadLimits resolve_load_limits(const ModelLoadLimits& requested, std::uintmax_t file_bytes);

// Thrown when the loading process ran out of its memory or time: front ends name the option that
// raises the limit.
class ModelLoadLimitExceeded : public InvalidArgument {
 public:
  enum class Limit { kMemory, kTime };
  ModelLoadLimitExceeded(Limit limit, const std::string& message) : InvalidArgument(message), limit_(limit) {}
  Limit limit() const { return limit_; }

 private:
  Limit limit_;
};

// load_model, run in a child process (fork) with `limits`, the model passed back through shared
// memory and checked. Everything load_model throws is thrown the same; besides, with one line naming
// the file:
// - ModelLoadLimitExceeded when the child allocates beyond its memory limit or runs beyond its time
//   (it is killed);
// - InvalidArgument when the child crashes ("the model loader crashed (SIGSEGV, Segmentation fault)",
//   with the last line it wrote to stderr, such as assimp's assertion), without a core dump.
// The child is a fork of the calling process, so call this before the process starts threads (the
// command line loads its model before it creates an OpenCL context): a lock that another thread
// holds at the fork stays held in the child (glibc's malloc and stdio locks excepted), and a child
// stuck on one ends at the time limit. The child can reuse the heap the caller holds free (glibc
// keeps what was freed for reuse): the memory limit counts it but cannot keep the child from
// using it, so in a process that holds more free than the limit, the child can use that much. (The
// command line loads with next to nothing free.) The memory limit is not applied under
// AddressSanitizer.
Model load_model_isolated(const std::string& path, std::vector<std::string>& warnings,
                          const ModelLoadLimits& limits = {});

}  // namespace clraster::io
