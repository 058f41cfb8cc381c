// Writes seed corpora for the fuzzers: the synthetic BSP and SGI files of
// the tests (tests/game_data.h). Usage: oovr-fuzz-seeds DIR
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "game_data.h"

namespace fs = std::filesystem;

static void write(const fs::path& p, const std::vector<uint8_t>& bytes) {
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: oovr-fuzz-seeds DIR\n");
    return 2;
  }
  const fs::path dir = argv[1];
  fs::create_directories(dir / "bsp");
  fs::create_directories(dir / "sgi");
  write(dir / "bsp" / "test.bsp", oovr::test::make_test_bsp());
  for (int channels = 1; channels <= 4; ++channels)
    for (bool rle : {false, true})
      write(dir / "sgi" / ("test-" + std::to_string(channels) + (rle ? "-rle" : "") + ".rgb"),
            oovr::test::make_test_sgi(11, 6, channels, rle));
  return 0;
}
