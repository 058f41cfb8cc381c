// Writes seed corpora for the fuzzers: the synthetic BSP and SGI files of
// the tests (tests/game_data.h) and shader scripts in the styles OpenArena
// and Nexuiz write them. Usage: oovr-fuzz-seeds DIR
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
  fs::create_directories(dir / "shader");
  write(dir / "bsp" / "test.bsp", oovr::test::make_test_bsp());
  for (int channels = 1; channels <= 4; ++channels)
    for (bool rle : {false, true})
      write(dir / "sgi" / ("test-" + std::to_string(channels) + (rle ? "-rle" : "") + ".rgb"),
            oovr::test::make_test_sgi(11, 6, channels, rle));
  // Every stage keyword oovr reads, in the forms the games use.
  std::ofstream(dir / "shader" / "stages.shader") << R"(textures/base/wall
{
  qer_editorimage textures/base/wall.tga
  cull none
  sort additive
  {
    map textures/base/wall.tga
    rgbGen identity
    tcMod scale 2 2
    tcMod scroll 0.1 -0.5
  }
  {
    map $lightmap
    blendFunc GL_DST_COLOR GL_ZERO
    tcGen lightmap
  }
  {
    clampmap textures/base/glow.jpg
    blendFunc add
    alphaFunc GE128
    depthWrite
    depthFunc equal
    rgbGen const ( 0.5 0.25 1 )
    alphaGen const 0.5
    detail
  }
  {
    animMap 10 textures/a.tga textures/b.tga
    blendfunc GL_SRC_ALPHA GL_ONE_MINUS_SRC_ALPHA
    tcMod rotate 30
    tcGen environment
  }
}
textures/sky/space
{
  surfaceparm sky
  surfaceparm nolightmap
  skyParms env/space - -
  { map textures/sky/clouds.tga blendFunc filter }
}
textures/fog/red
{
  fogparms ( 1 0 0 ) 128
  surfaceparm nodraw
}
)";
  std::ofstream(dir / "shader" / "nexuiz.shader") << R"(textures/eX/eX_q2_01
{
	qer_EditorImage textures/eX/eX_q2_01.tga
	{
		map textures/eX/eX_q2_01
	}
	{
		map $lightmap
	}
}
)";
  return 0;
}
