// Scenes as bytes and back (scene/scene_codec.h): what the cache of
// imported captures stores and reads back as untrusted input.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "apitrace_writer.h"
#include "oovr/pipeline/trace_cache.h"
#include "oovr/scene/formats/gl_trace.h"
#include "oovr/scene/load.h"
#include "oovr/scene/scene_codec.h"
#include "temp_dir.h"

namespace oovr {
namespace {

// A captured scene of two frames (a textured, coloured quad; a 2-D one).
Scene captured() {
  test::TraceWriter w;
  w.gl_viewport(64, 48);
  w.gl_texture_2x2(3, {1, 2, 3, 255, 4, 5, 6, 255, 7, 8, 9, 255, 10, 11, 12, 128});
  w.call("glEnable", {{"cap", w.e("GL_TEXTURE_2D", 0x0DE1)}});
  w.call("glEnableClientState", {{"array", w.e("GL_VERTEX_ARRAY", 0x8074)}});
  w.call("glEnableClientState", {{"array", w.e("GL_COLOR_ARRAY", 0x8076)}});
  for (int f = 0; f < 2; ++f) {
    const std::vector<float> xyz = {-1, -1, -5, 1, -1, -5, 1, 1, -5};
    const std::vector<uint8_t> rgba = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, uint8_t(100 + f)};
    const std::vector<uint16_t> idx = {0, 1, 2};
    w.gl_client_array("glColorPointer", 4, "GL_UNSIGNED_BYTE", 0x1401, rgba);
    w.gl_client_array("glVertexPointer", 3, "GL_FLOAT", 0x1406, xyz);
    w.call("glDrawElements", {{"mode", w.e("GL_TRIANGLES", 4)},
                              {"count", w.i(3)},
                              {"type", w.e("GL_UNSIGNED_SHORT", 0x1403)},
                              {"indices", w.blob(idx)}});
    w.call("glXSwapBuffers", {{"dpy", w.opaque(1)}, {"drawable", w.u(2)}});
  }
  GlTraceWindow win;
  win.count = 2;
  return import_gl_trace_bytes(w.finish(), "codec.trace", win);
}

TEST(SceneCodec, ScenesComeBackWhole) {
  for (const Scene& s : {load_scene("courtyard"), captured()}) {
    const std::string bytes = encode_scene(s);
    std::string why;
    const auto back = decode_scene(bytes, &why);
    ASSERT_TRUE(back) << s.name << ": " << why;
    EXPECT_EQ(encode_scene(*back), bytes) << s.name;
    EXPECT_EQ(scene_fingerprint(*back), scene_fingerprint(s)) << s.name;
    EXPECT_EQ(back->notes, s.notes);
    EXPECT_EQ(back->captured(), s.captured());
  }
}

TEST(SceneCodec, DamagedBytesAreRefusedWithAReason) {
  const std::string bytes = encode_scene(captured());
  // Every cut short of the whole.
  for (size_t cut = 0; cut < bytes.size(); cut += 1 + cut / 16) {
    std::string why;
    EXPECT_FALSE(decode_scene(bytes.substr(0, cut), &why)) << cut;
    EXPECT_FALSE(why.empty()) << cut;
  }
  // Every byte changed: refused, or a scene that still validates.
  for (size_t at = 0; at < bytes.size(); ++at) {
    std::string b = bytes;
    b[at] = char(b[at] ^ 0x5A);
    std::string why;
    if (const auto s = decode_scene(b, &why)) {
      EXPECT_NO_THROW(s->validate()) << at;
    }
  }
  std::string why;
  EXPECT_FALSE(decode_scene(bytes + "x", &why));
  EXPECT_EQ(why, "bytes after the scene");
}

TEST(SceneCodec, MipChainsMustBeOpenGLsShape) {
  // A level whose sides multiply to its bytes but are negative (-1 x -4
  // is 16 bytes once the sizes wrap), or a level larger than the one
  // before: the sampler would index outside the texels.
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{{-1, -4}, {2, 2}, {1, 4}}) {
    Scene s = captured();
    Texture& t = s.textures.front();
    t.mipmapped = true;
    build_mip_chain(t);
    ASSERT_EQ(t.levels.size(), 2u);
    t.levels[1].width = w;
    t.levels[1].height = h;
    t.levels[1].rgba.assign(16, 0);
    std::string why;
    EXPECT_FALSE(decode_scene(encode_scene(s), &why)) << w << "x" << h;
    EXPECT_NE(why.find("mip level of the wrong size"), std::string::npos) << why;
  }
}

TEST(SceneCodec, TheCacheHitsOnItsKeyAndMissesOnDamage) {
  const test::TempDir dir;
  const SceneCache cache(dir.path().string());
  const Scene s = captured();
  EXPECT_FALSE(cache.load("k"));
  cache.store("k", s);
  const auto hit = cache.load("k");
  ASSERT_TRUE(hit);
  EXPECT_EQ(scene_fingerprint(*hit), scene_fingerprint(s));
  EXPECT_FALSE(cache.load("another key"));
  // A flipped byte in the payload: a miss that says why.
  for (const auto& e : std::filesystem::directory_iterator(dir.path())) {
    std::fstream f(e.path(), std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(-5, std::ios::end);
    f.put('\x7f');
  }
  std::string why;
  EXPECT_FALSE(cache.load("k", &why));
  EXPECT_NE(why.find("checksum mismatch"), std::string::npos) << why;
}

}  // namespace
}  // namespace oovr
