#include "io/isolated_loader.hpp"

#include "io/format.hpp"

#include <malloc.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <new>
#include <string_view>
#include <thread>

namespace clraster::io {
namespace {

// Why fork() and not a re-executed binary: load_model is a library function that the command line,
// the tests and the examples call, and re-executing /proc/self/exe would need a hidden entry point
// in every one of their main()s; a forked child also starts with the parser already in memory.
// The price is the precondition in the header (no other threads at the fork), which the command
// line meets by loading before it creates any OpenCL context.

// How the child ends, besides by a signal: 0 once it passed back a model or load_model's error.
constexpr int kExitOutOfMemory = 3;
constexpr int kExitCannotPassBack = 4;

// What the child passes back: the tag, then a model or an error message, then the tag again.
constexpr std::string_view kResultTag = "clraster-model-1";
enum class Outcome : std::uint64_t { kModel = 1, kError = 2 };

constexpr std::size_t kMiB = std::size_t{1} << 20;

class UniqueFd {
 public:
  explicit UniqueFd(int fd) : fd_(fd) {}
  ~UniqueFd() {
    if (fd_ >= 0) ::close(fd_);
  }
  UniqueFd(const UniqueFd&) = delete;
  UniqueFd& operator=(const UniqueFd&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

[[noreturn]] void fail_system(const std::string& what) {
  throw Error("cannot run the model loader: " + what + ": " + std::strerror(errno));
}

// ---- The result, written by the child and read by the parent --------------------------------------

// Writes straight into the shared memory file: a model's arrays are not copied on the way.
class ResultWriter {
 public:
  explicit ResultWriter(int fd) : fd_(fd) {}

  void raw(const void* data, std::size_t size) {
    const char* bytes = static_cast<const char*>(data);
    while (size > 0) {
      const ssize_t written = ::write(fd_, bytes, size);
      if (written < 0 && errno == EINTR) continue;
      if (written <= 0) ::_exit(kExitCannotPassBack);
      bytes += written;
      size -= static_cast<std::size_t>(written);
    }
  }
  void number(std::uint64_t value) { raw(&value, sizeof value); }
  void text(std::string_view value) {
    number(value.size());
    raw(value.data(), value.size());
  }
  template <typename T>
  void array(const std::vector<T>& values) {
    number(values.size());
    raw(values.data(), values.size() * sizeof(T));
  }
  void texts(const std::vector<std::string>& values) {
    number(values.size());
    for (const std::string& value : values) text(value);
  }

 private:
  int fd_;
};

void write_model(ResultWriter& out, const Model& model, const std::vector<std::string>& warnings) {
  out.number(static_cast<std::uint64_t>(Outcome::kModel));
  out.texts(warnings);
  out.array(model.positions);
  out.array(model.normals);
  out.array(model.texcoords);
  out.array(model.indices);
  out.number(model.materials.size());
  for (const Material& material : model.materials) {
    out.text(material.name);
    out.raw(material.base_color_factor.data(), sizeof material.base_color_factor);
    out.number(material.base_color_texture.has_value());
    if (!material.base_color_texture) continue;
    const MaterialTexture& texture = *material.base_color_texture;
    out.text(texture.reference);
    out.text(texture.file);
    out.array(texture.encoded);
    out.text(texture.format_hint);
    out.number(texture.uv_channel);
  }
  out.array(model.parts);
  out.texts(model.material_warnings);
  out.number(model.triangles_dropped);
}

// Reads what the child passed back, every length checked against what is there before anything is
// allocated for it: a child whose memory a parser corrupted could pass back anything.
class ResultReader {
 public:
  ResultReader(std::string_view bytes, const std::string& path) : rest_(bytes), path_(path) {}

  [[noreturn]] void malformed() const {
    throw InvalidArgument(describe_load_error(path_, "the model loader passed back a malformed result"));
  }
  const char* take(std::size_t size) {
    if (size > rest_.size()) malformed();
    const char* data = rest_.data();
    rest_.remove_prefix(size);
    return data;
  }
  std::uint64_t number() {
    std::uint64_t value = 0;
    std::memcpy(&value, take(sizeof value), sizeof value);
    return value;
  }
  std::string text() {
    const std::uint64_t size = number();
    if (size > rest_.size()) malformed();
    return std::string(take(size), size);
  }
  template <typename T>
  std::vector<T> array() {
    const std::uint64_t count = number();
    if (count > rest_.size() / sizeof(T)) malformed();
    const char* bytes = take(count * sizeof(T));
    std::vector<T> values(count);
    if (count > 0) std::memcpy(values.data(), bytes, count * sizeof(T));  // data() can be null otherwise
    return values;
  }
  std::vector<std::string> texts() {
    const std::uint64_t count = number();
    if (count > rest_.size() / sizeof(std::uint64_t)) malformed();  // each has its length at least
    std::vector<std::string> values;
    for (std::uint64_t i = 0; i < count; ++i) values.push_back(text());
    return values;
  }
  void expect(std::string_view tag) {
    if (std::string_view(take(tag.size()), tag.size()) != tag) malformed();
  }
  bool at_end() const { return rest_.empty(); }

 private:
  std::string_view rest_;
  const std::string& path_;
};

Model read_model(ResultReader& in, std::vector<std::string>& warnings) {
  warnings = in.texts();
  Model model;
  model.positions = in.array<float>();
  model.normals = in.array<float>();
  model.texcoords = in.array<float>();
  model.indices = in.array<std::uint32_t>();
  const std::uint64_t materials = in.number();
  for (std::uint64_t m = 0; m < materials; ++m) {
    Material& material = model.materials.emplace_back();
    material.name = in.text();
    std::memcpy(material.base_color_factor.data(), in.take(sizeof material.base_color_factor),
                sizeof material.base_color_factor);
    if (in.number() == 0) continue;
    MaterialTexture& texture = material.base_color_texture.emplace();
    texture.reference = in.text();
    texture.file = in.text();
    texture.encoded = in.array<std::byte>();
    texture.format_hint = in.text();
    texture.uv_channel = static_cast<unsigned>(in.number());
  }
  model.parts = in.array<ModelPart>();
  model.material_warnings = in.texts();
  model.triangles_dropped = in.number();
  return model;
}

// What load_model promises of a model, checked again on what came back.
bool well_formed(const Model& model) {
  const std::size_t vertices = model.vertex_count();
  if (model.positions.size() % 3 != 0 || model.normals.size() != model.positions.size() ||
      (!model.texcoords.empty() && model.texcoords.size() != 2 * vertices) || model.indices.size() % 3 != 0 ||
      model.indices.empty()) {
    return false;
  }
  if (std::any_of(model.indices.begin(), model.indices.end(), [&](std::uint32_t v) { return v >= vertices; })) {
    return false;
  }
  std::uint64_t next_index = 0;
  for (const ModelPart& part : model.parts) {
    if (part.first_index != next_index || part.material >= model.materials.size()) return false;
    next_index += part.index_count;
  }
  return next_index == model.indices.size();
}

// ---- The child ------------------------------------------------------------------------------------

[[noreturn]] void load_in_child(const std::string& path, pid_t parent, int result_fd, int messages_fd,
                                std::optional<rlim_t> data_limit) {
  // Killed with its parent; a crash is the parent's to report, not a core file's.
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) ::_exit(kExitCannotPassBack);
  ::prctl(PR_SET_DUMPABLE, 0);
  const rlimit no_core{0, 0};
  ::setrlimit(RLIMIT_CORE, &no_core);
  // What a parser says as it dies (assimp's assertions) goes into the parent's message.
  ::dup2(messages_fd, STDERR_FILENO);
  // RLIMIT_DATA rather than RLIMIT_AS: it also bounds malloc's arenas of the caller's former
  // threads, which grow within address space they reserved already, and it leaves out the mapped
  // model file (read-only).
  if (data_limit) {
    const rlimit limit{*data_limit, *data_limit};
    ::setrlimit(RLIMIT_DATA, &limit);
  }
  std::set_new_handler([] { ::_exit(kExitOutOfMemory); });

  ResultWriter out(result_fd);
  out.raw(kResultTag.data(), kResultTag.size());
  try {
    std::vector<std::string> warnings;
    const Model model = load_model(path, warnings);
    write_model(out, model, warnings);
  } catch (const InvalidArgument& error) {
    out.number(static_cast<std::uint64_t>(Outcome::kError));
    out.text(error.what());
  } catch (const std::exception& error) {
    out.number(static_cast<std::uint64_t>(Outcome::kError));
    out.text(describe_load_error(path, error.what()));
  }
  out.raw(kResultTag.data(), kResultTag.size());
  ::_exit(0);
}

// ---- The parent -----------------------------------------------------------------------------------

// The memory the child starts with, as its limit counts memory: the process's private writable
// mappings (Linux's VmData, what RLIMIT_DATA bounds: heaps, anonymous mappings, malloc's arenas as
// they grow), less the heap that malloc holds free, which the child reuses before it maps more and
// which its limit counts too (glibc's count of free bytes in its arenas).
std::size_t data_in_use() {
  std::ifstream status("/proc/self/status");
  std::size_t kilobytes = 0;
  for (std::string line; std::getline(status, line);) {
    if (line.starts_with("VmData:")) kilobytes = std::stoull(line.substr(7));
  }
  const std::size_t mapped = kilobytes * 1024;
  return mapped - std::min(mapped, ::mallinfo2().fordblks);
}

struct ChildEnd {
  bool timed_out = false;
  int status = 0;  // waitpid's
};

// Waits for the child, killing it at the deadline.
ChildEnd wait_for(pid_t child, std::chrono::milliseconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  auto pause = std::chrono::microseconds(200);
  ChildEnd end;
  for (;;) {
    const pid_t waited = ::waitpid(child, &end.status, WNOHANG);
    if (waited == child) return end;
    if (waited < 0 && errno != EINTR) fail_system("waitpid");
    if (std::chrono::steady_clock::now() >= deadline) {
      ::kill(child, SIGKILL);
      while (::waitpid(child, &end.status, 0) < 0 && errno == EINTR) {
      }
      end.timed_out = true;
      return end;
    }
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, std::chrono::microseconds(10000));
  }
}

// The bytes of a memory file, mapped; unmapped on destruction.
class Mapped {
 public:
  explicit Mapped(int fd) {
    struct stat status {};
    if (::fstat(fd, &status) != 0) fail_system("fstat");
    size_ = static_cast<std::size_t>(status.st_size);
    if (size_ == 0) return;
    data_ = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
    if (data_ == MAP_FAILED) fail_system("mmap");
  }
  ~Mapped() {
    if (size_ > 0) ::munmap(data_, size_);
  }
  Mapped(const Mapped&) = delete;
  Mapped& operator=(const Mapped&) = delete;
  std::string_view bytes() const { return {static_cast<const char*>(data_), size_}; }

 private:
  void* data_ = nullptr;
  std::size_t size_ = 0;
};

// The last line the child wrote to stderr, at most a few hundred characters of it.
std::string last_line(int fd) {
  const Mapped messages(fd);
  std::string_view text = messages.bytes();
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.remove_suffix(1);
  const std::size_t start = text.find_last_of('\n');
  std::string line(text.substr(start == std::string_view::npos ? 0 : start + 1));
  constexpr std::size_t kMaxLength = 300;
  if (line.size() > kMaxLength) line = line.substr(0, kMaxLength - 3) + "...";
  return line;
}

std::string signal_name(int signal) {
  const char* abbreviation = ::sigabbrev_np(signal);
  const std::string name =
      abbreviation != nullptr ? std::string("SIG") + abbreviation : "signal " + std::to_string(signal);
  return name + ", " + ::strsignal(signal);
}

}  // namespace

ResolvedLoadLimits resolve_load_limits(const ModelLoadLimits& requested, std::uintmax_t file_bytes) {
  const std::uintmax_t file_mib = (file_bytes + kMiB - 1) / kMiB;
  return {requested.memory_bytes.value_or(
              std::max<std::uintmax_t>(kLoadMemoryFloor, kLoadMemoryPerFileByte * file_bytes)),
          requested.time.value_or(std::max<std::chrono::milliseconds>(
              kLoadTimeFloor, kLoadTimePerMiB * static_cast<std::chrono::seconds::rep>(file_mib)))};
}

Model load_model_isolated(const std::string& path, std::vector<std::string>& warnings,
                          const ModelLoadLimits& limits) {
  struct stat file {};
  const std::uintmax_t file_bytes = ::stat(path.c_str(), &file) == 0 ? static_cast<std::uintmax_t>(file.st_size) : 0;
  const ResolvedLoadLimits resolved = resolve_load_limits(limits, file_bytes);

  const UniqueFd result(::memfd_create("clraster-model", MFD_CLOEXEC));
  const UniqueFd messages(::memfd_create("clraster-model-stderr", MFD_CLOEXEC));
  if (result.get() < 0 || messages.get() < 0) fail_system("memfd_create");
  std::optional<rlim_t> data_limit;
  if (!kBuiltWithAddressSanitizer) data_limit = data_in_use() + resolved.memory_bytes;

  const pid_t parent = ::getpid();
  const pid_t child = ::fork();
  if (child < 0) fail_system("fork");
  if (child == 0) load_in_child(path, parent, result.get(), messages.get(), data_limit);

  const ChildEnd end = wait_for(child, resolved.time);
  const auto fail_with = [&](const std::string& reason) { throw InvalidArgument(describe_load_error(path, reason)); };
  if (end.timed_out) {
    throw ModelLoadLimitExceeded(
        ModelLoadLimitExceeded::Limit::kTime,
        describe_load_error(path, "the model loader ran longer than its time limit of " +
                                      format_number(static_cast<double>(resolved.time.count()) / 1000) + " s"));
  }
  // What a dying child said last (assimp's assertion, AddressSanitizer's report) follows the reason.
  const auto and_what_it_said = [&](const std::string& reason) {
    const std::string said = last_line(messages.get());
    return said.empty() ? reason : reason + ": " + said;
  };
  if (WIFSIGNALED(end.status)) {
    fail_with(and_what_it_said("the model loader crashed (" + signal_name(WTERMSIG(end.status)) + ")"));
  }
  const int code = WEXITSTATUS(end.status);
  if (code == kExitOutOfMemory) {
    throw ModelLoadLimitExceeded(ModelLoadLimitExceeded::Limit::kMemory,
                                 describe_load_error(path, "the model loader needed more than its memory limit of " +
                                                               std::to_string(resolved.memory_bytes / kMiB) + " MiB"));
  }
  if (code == kExitCannotPassBack) fail_with("the model loader could not pass the model back");
  if (code != 0) fail_with(and_what_it_said("the model loader exited with code " + std::to_string(code)));

  const Mapped mapped(result.get());
  ResultReader in(mapped.bytes(), path);
  in.expect(kResultTag);
  const auto outcome = static_cast<Outcome>(in.number());
  if (outcome == Outcome::kError) {
    const std::string message = in.text();
    in.expect(kResultTag);
    throw InvalidArgument(message);
  }
  if (outcome != Outcome::kModel) in.malformed();
  std::vector<std::string> child_warnings;
  Model model = read_model(in, child_warnings);
  in.expect(kResultTag);
  if (!in.at_end() || !well_formed(model)) in.malformed();
  warnings.insert(warnings.end(), child_warnings.begin(), child_warnings.end());
  return model;
}

}  // namespace clraster::io
