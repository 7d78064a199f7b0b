// libFuzzer target for the model loader: the input is a model file of the format whose extension
// CLRASTER_FUZZ_EXTENSION names (one executable per format), loaded in this process with
// load_model, so that the fuzzer sees a crash (load_model_isolated would turn it into an error).
// load_model may refuse a file with InvalidArgument; anything else escaping it is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "clraster/clraster.hpp"
#include "io/model_loader.hpp"

namespace {

// A file of this process's own: assimp reads paths, and picks its reader by the extension.
const std::string& model_path() {
  static const std::string path = [] {
    const std::filesystem::path directory =
        std::filesystem::temp_directory_path() / ("clraster-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(directory);
    return (directory / ("model" CLRASTER_FUZZ_EXTENSION)).string();
  }();
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::ofstream(model_path(), std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  std::vector<std::string> warnings;
  try {
    clraster::io::load_model(model_path(), warnings);
  } catch (const clraster::InvalidArgument&) {
  }
  return 0;
}
