// The on-disk cache of built programs: it keeps within its limit by removing the entries used
// longest ago, where loading an entry counts as using it.
#include "api/impl.hpp"
#include "runtime/program_cache.hpp"
#include "support/test_support.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <unistd.h>

namespace clraster::test {
namespace {

namespace fs = std::filesystem;

std::string numbered_kernel(int n) {
  return "__kernel void number_" + std::to_string(n) + "(__global int* out) { out[0] = " + std::to_string(n) + "; }\n";
}

// Which numbered kernels the directory holds entries of (an entry stores its whole key, source included).
std::set<int> cached_kernels(const fs::path& directory) {
  std::set<int> numbers;
  for (const fs::directory_entry& entry : fs::directory_iterator(directory)) {
    std::ifstream in(entry.path(), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    for (int n = 0; n < 10; ++n) {
      if (bytes.find("void number_" + std::to_string(n) + "(") != std::string::npos) numbers.insert(n);
    }
  }
  return numbers;
}

TEST(ProgramCache, RemovesTheEntriesUsedLongestAgoBeyondItsLimit) {
  const ContextState& state = *shared_context().impl().state;
  const fs::path directory = fs::temp_directory_path() / ("clraster-program-cache-test-" + std::to_string(::getpid()));
  fs::remove_all(directory);
  // Each cache object is a new run: its programs come from the directory or are built and stored.
  const auto run = [&](std::uintmax_t limit, std::initializer_list<int> kernels) {
    runtime::ProgramCache cache(state.context, state.device, directory.string(), limit);
    for (const int n : kernels) cache.get("number.cl", numbered_kernel(n), "");
  };
  run(std::uintmax_t{1} << 30, {0});
  std::uintmax_t entry_bytes = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(directory)) entry_bytes += entry.file_size();
  ASSERT_GT(entry_bytes, 0u);

  const std::uintmax_t room_for_two = entry_bytes * 5 / 2;
  run(room_for_two, {1});
  EXPECT_EQ(cached_kernels(directory), (std::set<int>{0, 1}));
  run(room_for_two, {0});  // loaded: 0 is now the one used last
  run(room_for_two, {2});  // a third entry: 1, used longest ago, goes
  EXPECT_EQ(cached_kernels(directory), (std::set<int>{0, 2}));
  // Files of someone else's in the directory are neither counted nor removed, even the oldest.
  const fs::path others = directory / "0123456789abcdef.bin";
  std::ofstream(others) << "not a program";
  fs::last_write_time(others, fs::file_time_type::clock::now() - std::chrono::hours(24 * 365));
  run(room_for_two, {3, 4});
  EXPECT_TRUE(fs::exists(others));
  fs::remove(others);
  EXPECT_EQ(cached_kernels(directory), (std::set<int>{3, 4}));
  fs::remove_all(directory);
}

}  // namespace
}  // namespace clraster::test
