// libFuzzer target: the pk3 file system (libzip underneath, with
// ZIP_CHECKCONS and a CRC check at each entry's end). The input is written
// as the only archive of a folder, which is opened, listed and read whole.
// Bad input must be an Error, never a crash, a hang or more memory than an
// entry's bound.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "oovr/core/error.h"
#include "oovr/scene/formats/pk3.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::filesystem::path dir = [] {
    const auto d = std::filesystem::temp_directory_path() / ("oovr-fuzz-pk3-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  std::ofstream(dir / "pak0.pk3", std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), std::streamsize(size));
  try {
    const oovr::Pk3FileSystem fs(dir.string());
    for (const std::string& path : fs.list("", "")) {
      try {
        (void)fs.read(path, 1 << 20);
      } catch (const oovr::Error&) {
      }
    }
  } catch (const oovr::Error&) {
  }
  return 0;
}
