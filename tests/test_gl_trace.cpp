// The OpenGL interpreter (scene/formats/gl_trace.h) on traces written by
// tests/apitrace_writer.h: what each call becomes in the scene, and the
// calls and state it refuses.
#include <gtest/gtest.h>

#include <functional>

#include "apitrace_writer.h"
#include "oovr/core/error.h"
#include "oovr/pipeline/pipeline.h"
#include "oovr/scene/formats/gl_programs.h"
#include "oovr/scene/formats/gl_trace.h"
#include "oovr/scene/stereo.h"

namespace oovr {
namespace {

using test::TraceWriter;

// A GL 1.x game in miniature: the calls ioquake3's opengl1 renderer makes
// for a frame, written as apitrace records them.
class Game {
 public:
  TraceWriter w;

  Game() {
    w.gl_viewport(64, 48);
    w.gl_texture_2x2(7, {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 128});
    w.call("glTexParameterf", {{"target", w.e("GL_TEXTURE_2D", 0x0DE1)},
                               {"pname", w.e("GL_TEXTURE_MIN_FILTER", 0x2801)},
                               {"param", w.f(float(0x2601))}});  // GL_LINEAR: no mipmaps needed
  }

  void enable(const char* name, int64_t cap, bool on = true) { w.call(on ? "glEnable" : "glDisable", {{"cap", w.e(name, cap)}}); }
  void matrix(const char* mode, int64_t value, const std::vector<float>& m) {
    w.call("glMatrixMode", {{"mode", w.e(mode, value)}});
    std::vector<std::string> items;
    for (float f : m) items.push_back(w.f(f));
    w.call("glLoadMatrixf", {{"m", w.array(items)}});
  }
  void perspective() {
    // A 90-degree frustum, near 1, far 100.
    matrix("GL_PROJECTION", 0x1701, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, -101.0f / 99, -1, 0, 0, -200.0f / 99, 0});
    matrix("GL_MODELVIEW", 0x1700, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1});
  }
  void ortho() {
    w.call("glMatrixMode", {{"mode", w.e("GL_PROJECTION", 0x1701)}});
    w.call("glLoadIdentity", {});
    w.call("glOrtho",
           {{"left", w.d(0)}, {"right", w.d(64)}, {"bottom", w.d(48)}, {"top", w.d(0)}, {"zNear", w.d(0)}, {"zFar", w.d(1)}});
    w.call("glMatrixMode", {{"mode", w.e("GL_MODELVIEW", 0x1700)}});
    w.call("glLoadIdentity", {});
  }
  // A textured, vertex-coloured quad at depth z, drawn from client arrays
  // with glDrawElements, as apitrace records it (fake pointer calls first).
  void quad(float z, uint8_t red = 255) {
    const std::vector<float> xyz = {-1, -1, z, 1, -1, z, 1, 1, z, -1, 1, z};
    const std::vector<float> st = {0, 0, 1, 0, 1, 1, 0, 1};
    const std::vector<uint8_t> rgba = {red, 255, 255, 255, red, 255, 255, 255, red, 255, 255, 255, red, 255, 255, 255};
    const std::vector<uint32_t> idx = {0, 1, 2, 0, 2, 3};
    w.call("glEnableClientState", {{"array", w.e("GL_VERTEX_ARRAY", 0x8074)}});
    w.call("glEnableClientState", {{"array", w.e("GL_TEXTURE_COORD_ARRAY", 0x8078)}});
    w.call("glEnableClientState", {{"array", w.e("GL_COLOR_ARRAY", 0x8076)}});
    w.gl_client_array("glTexCoordPointer", 2, "GL_FLOAT", 0x1406, st);
    w.gl_client_array("glColorPointer", 4, "GL_UNSIGNED_BYTE", 0x1401, rgba);
    w.gl_client_array("glVertexPointer", 3, "GL_FLOAT", 0x1406, xyz);
    w.call("glDrawElements", {{"mode", w.e("GL_TRIANGLES", 4)},
                              {"count", w.i(6)},
                              {"type", w.e("GL_UNSIGNED_INT", 0x1405)},
                              {"indices", w.blob(idx)}});
  }
  void swap() { w.call("glXSwapBuffers", {{"dpy", w.opaque(1)}, {"drawable", w.u(2)}}); }

  Scene import(int first = 0, int count = 1) const {
    GlTraceWindow win;
    win.first = first;
    win.count = count;
    return import_gl_trace_bytes(w.finish(), "game.trace", win);
  }
};

TEST(GlTrace, AClientArrayDrawBecomesAnObjectWithItsMeshTextureAndState) {
  Game g;
  g.enable("GL_TEXTURE_2D", 0x0DE1);
  g.enable("GL_DEPTH_TEST", 0x0B71);
  g.enable("GL_BLEND", 0x0BE2);
  g.w.call("glBlendFunc", {{"sfactor", g.w.e("GL_SRC_ALPHA", 0x302)}, {"dfactor", g.w.e("GL_ONE_MINUS_SRC_ALPHA", 0x303)}});
  g.w.call("glDepthFunc", {{"func", g.w.e("GL_LEQUAL", 0x203)}});
  g.w.call("glGetError", {}, g.w.u(0));  // harmless
  g.perspective();
  g.quad(-5, 128);
  g.swap();
  const Scene s = g.import();
  ASSERT_TRUE(s.captured());
  ASSERT_EQ(s.frame_objects.size(), 1u);
  ASSERT_EQ(s.camera.frames.size(), 1u);
  ASSERT_EQ(s.draws(0).size(), 1u);
  const Object& o = s.draws(0)[0];
  EXPECT_EQ(o.view, DrawView::captured);
  const Mesh& m = s.meshes[size_t(o.mesh)];
  EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
  ASSERT_EQ(m.vertices.size(), 4u);
  EXPECT_EQ(m.vertices[2].position.x, 1.0f);
  EXPECT_EQ(m.vertices[2].position.z, -5.0f);
  EXPECT_EQ(m.vertices[2].uv.y, 1.0f);
  ASSERT_EQ(m.colours.size(), 4u);
  EXPECT_EQ(m.colours[0], 0xFFFFFF80u);
  const Pass& p = s.pass_of(o);
  ASSERT_EQ(p.layers.size(), 1u);
  const Texture& t = s.textures[size_t(p.layers[0].texture)];
  EXPECT_EQ(t.width(), 2);
  EXPECT_FALSE(t.mipmapped);
  EXPECT_FALSE(t.opaque);
  EXPECT_EQ(t.levels[0].rgba[4 * 1 + 1], 255);  // texel 1 is green
  EXPECT_EQ(p.src, BlendFactor::src_alpha);
  EXPECT_EQ(p.dst, BlendFactor::one_minus_src_alpha);
  EXPECT_EQ(p.depth_func, DepthFunc::lequal);
  EXPECT_TRUE(s.materials[size_t(o.material)].two_sided);  // GL_CULL_FACE was never enabled
  EXPECT_FLOAT_EQ(o.clip_from_eye.at(3, 2), -1.0f);
}

TEST(GlTrace, TheSameDrawInTwoFramesIsOneMeshAndTheWindowPicksFrames) {
  Game g;
  g.perspective();
  for (int f = 0; f < 3; ++f) {
    g.quad(-5, uint8_t(f == 2 ? 9 : 255));
    g.swap();
  }
  const Scene s = g.import(1, 2);
  ASSERT_EQ(s.frame_objects.size(), 2u);
  EXPECT_EQ(s.draws(0)[0].mesh != s.draws(1)[0].mesh, true);  // frame 2's colours differ
  const Scene t = g.import(0, 2);
  EXPECT_EQ(t.draws(0)[0].mesh, t.draws(1)[0].mesh);
  EXPECT_EQ(t.meshes.size(), 1u);
  EXPECT_THROW(g.import(2, 2), Error);
  try {
    g.import(5, 1);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("has 3 frames"), std::string::npos) << e.what();
  }
}

TEST(GlTrace, ImmediateModeAndAnOrthographicProjectionMakeA2DDraw) {
  Game g;
  g.ortho();
  g.w.call("glColor4f", {{"red", g.w.f(1)}, {"green", g.w.f(0)}, {"blue", g.w.f(0)}, {"alpha", g.w.f(1)}});
  g.w.call("glBegin", {{"mode", g.w.e("GL_QUADS", 7)}});
  for (auto [x, y] : std::vector<std::pair<float, float>>{{0, 0}, {32, 0}, {32, 24}, {0, 24}}) {
    g.w.call("glTexCoord2f", {{"s", g.w.f(x / 32)}, {"t", g.w.f(y / 24)}});
    g.w.call("glVertex2f", {{"x", g.w.f(x)}, {"y", g.w.f(y)}});
  }
  g.w.call("glEnd", {});
  g.swap();
  const Scene s = g.import();
  ASSERT_EQ(s.draws(0).size(), 1u);
  const Object& o = s.draws(0)[0];
  EXPECT_EQ(o.view, DrawView::screen);
  const Mesh& m = s.meshes[size_t(o.mesh)];
  EXPECT_EQ(m.triangle_count(), 2u);
  EXPECT_EQ(m.colours[0], 0xFF0000FFu);
  EXPECT_TRUE(s.pass_of(o).layers.empty());  // GL_TEXTURE_2D is off

  // Drawn alike in both eyes: the red quad covers the top-left quarter of each.
  StereoRig rig;
  rig.eye_width = 64;
  rig.eye_height = 48;
  const StereoView view = make_stereo_view(s.camera, 0, rig);
  const FrameOutput out = render_frame(s, view, PipelineSettings{}, 0);
  for (int eye = 0; eye < 2; ++eye) {
    const uint8_t* inside = &out.colour.rgba[(size_t(40) * 128 + size_t(eye * 64 + 10)) * 4];  // row 40 from the bottom
    const uint8_t* outside = &out.colour.rgba[(size_t(10) * 128 + size_t(eye * 64 + 50)) * 4];
    EXPECT_EQ(inside[0], 255) << eye;
    EXPECT_EQ(inside[1], 0) << eye;
    EXPECT_EQ(outside[0], 0) << eye;
  }
}

TEST(GlTrace, A3DDrawIsReprojectedForEachEye) {
  Game g;
  g.perspective();
  g.quad(-2);  // near: a large parallax
  g.swap();
  const Scene s = g.import();
  StereoRig rig;
  rig.eye_width = 64;
  rig.eye_height = 48;
  rig.ipd_m = 0.0254f;  // one game unit (an inch): each eye half a unit off the head
  const FrameOutput out = render_frame(s, make_stereo_view(s.camera, 0, rig), PipelineSettings{}, 0);
  // The quad spans x from -1 to 1 at depth 2: half the width of each
  // eye's view, shifted right in the left eye and left in the right eye.
  const auto lit = [&](int x) { return out.colour.rgba[(size_t(24) * 128 + size_t(x)) * 4] > 0; };
  int left_first = -1, right_first = -1;
  for (int x = 0; x < 64; ++x)
    if (lit(x) && left_first < 0) left_first = x;
  for (int x = 64; x < 128; ++x)
    if (lit(x) && right_first < 0) right_first = x - 64;
  ASSERT_GE(left_first, 0);
  ASSERT_GE(right_first, 0);
  EXPECT_GT(left_first, right_first);
}

TEST(GlTrace, AShadersNextStageAndThe2DOverlayKeepTheirOrder) {
  Game g;
  g.perspective();
  g.quad(-5);
  g.quad(-5);  // the same surface again: its next stage
  g.quad(-7);  // another surface: free to move
  g.ortho();
  g.quad(0.5f);  // 2-D: after the world
  g.swap();
  const Scene s = g.import();
  const auto& d = s.draws(0);
  ASSERT_EQ(d.size(), 4u);
  EXPECT_TRUE(d[0].after.empty());
  EXPECT_EQ(d[1].after, std::vector<uint32_t>{0});
  EXPECT_TRUE(d[2].after.empty());
  EXPECT_EQ(d[3].after, std::vector<uint32_t>{2});
  EXPECT_EQ(d[3].view, DrawView::screen);
}

// The frame ends; its import must be an error naming the capture, the
// frame and each of `words`.
template <class G>
void expect_refused(G& g, const std::vector<std::string>& words) {
  g.swap();
  try {
    g.import();
    ADD_FAILURE() << "accepted; expected an error with: " << words.front();
  } catch (const Error& e) {
    const std::string what = e.what();
    for (const auto& w : words) EXPECT_NE(what.find(w), std::string::npos) << what;
    EXPECT_NE(what.find("frame 0"), std::string::npos) << what;
    EXPECT_NE(what.find("game.trace"), std::string::npos) << what;
  }
}
template <class G>
void expect_refused(G& g, const std::string& words) {
  expect_refused(g, std::vector<std::string>{words});
}

TEST(GlTrace, StateItDoesNotModelIsRefusedAtTheDraw) {
  {
    Game g;
    g.perspective();
    g.enable("GL_FOG", 0x0B60);
    g.quad(-5);
    expect_refused(g, "fog (GL_FOG)");
  }
  {
    Game g;  // fog enabled and disabled again before the draw: harmless
    g.perspective();
    g.enable("GL_FOG", 0x0B60);
    g.enable("GL_FOG", 0x0B60, false);
    g.quad(-5);
    g.swap();
    EXPECT_EQ(g.import().draws(0).size(), 1u);
  }
  {
    Game g;
    g.perspective();
    g.w.call("glBegin", {{"mode", g.w.e("GL_LINES", 1)}});
    g.w.call("glVertex2f", {{"x", g.w.f(0)}, {"y", g.w.f(0)}});
    g.w.call("glVertex2f", {{"x", g.w.f(1)}, {"y", g.w.f(1)}});
    g.w.call("glEnd", {});
    expect_refused(g, "points or lines");
  }
  {
    Game g;
    g.w.call("glAccum", {{"op", g.w.e("GL_ACCUM", 0x0100)}, {"value", g.w.f(1)}});
    expect_refused(g, "a call (glAccum), which oovr's OpenGL interpreter does not model");
  }
  {
    Game g;
    g.perspective();
    g.quad(-5);
    // An index past the recorded vertex array.
    const std::vector<uint32_t> idx = {0, 1, 9};
    g.w.call("glDrawElements", {{"mode", g.w.e("GL_TRIANGLES", 4)},
                                {"count", g.w.i(3)},
                                {"type", g.w.e("GL_UNSIGNED_INT", 0x1405)},
                                {"indices", g.w.blob(idx)}});
    expect_refused(g, "outside the vertex array");
  }
}

// Texture environments of two units: unit 0 modulates texture 7 (not
// opaque); unit 1 holds opaque texture 8 and gets `setup`'s GL_COMBINE
// state (or none); then a quad is drawn.
// Opaque texture 8 on unit 1, enabled (unit 1 left active).
void second_unit(Game& g) {
  g.w.call("glActiveTexture", {{"texture", g.w.e("GL_TEXTURE1", 0x84C1)}});
  g.w.gl_texture_2x2(8, {10, 20, 30, 255, 40, 50, 60, 255, 70, 80, 90, 255, 100, 110, 120, 255});
  g.w.call("glTexParameterf", {{"target", g.w.e("GL_TEXTURE_2D", 0x0DE1)},
                               {"pname", g.w.e("GL_TEXTURE_MIN_FILTER", 0x2801)},
                               {"param", g.w.f(float(0x2601))}});
  g.enable("GL_TEXTURE_2D", 0x0DE1);
}

Game two_units(const std::function<void(Game&)>& setup) {
  Game g;
  g.enable("GL_TEXTURE_2D", 0x0DE1);
  second_unit(g);
  setup(g);
  g.w.call("glActiveTexture", {{"texture", g.w.e("GL_TEXTURE0", 0x84C0)}});
  g.perspective();
  g.quad(-5);
  return g;
}

void env(Game& g, const char* pname, int64_t pvalue, const char* name, int64_t value) {
  g.w.call("glTexEnvi",
           {{"target", g.w.e("GL_TEXTURE_ENV", 0x2300)}, {"pname", g.w.e(pname, pvalue)}, {"param", g.w.e(name, value)}});
}

void rgb_scale(Game& g, float scale) {
  g.w.call("glTexEnvf",
           {{"target", g.w.e("GL_TEXTURE_ENV", 0x2300)}, {"pname", g.w.e("GL_RGB_SCALE", 0x8573)}, {"param", g.w.f(scale)}});
}

TEST(GlTrace, ACombineThatModulatesOrAddsBecomesALayerAndItsScale) {
  // Quake 3's and DarkPlaces' overbright lightmap: previous x texel x 2.
  Game g = two_units([](Game& u) {
    env(u, "GL_TEXTURE_ENV_MODE", 0x2200, "GL_COMBINE", 0x8570);
    env(u, "GL_SRC0_RGB", 0x8580, "GL_PREVIOUS", 0x8578);  // the operands swapped: the same product
    env(u, "GL_SRC1_RGB", 0x8581, "GL_TEXTURE", 0x1702);
    rgb_scale(u, 2);
  });
  g.swap();
  const Scene s = g.import();
  const Pass& p = s.pass_of(s.draws(0)[0]);
  ASSERT_EQ(p.layers.size(), 2u);
  EXPECT_EQ(p.layers[0].scale, 1.0f);
  EXPECT_EQ(p.layers[1].combine, Combine::modulate);
  EXPECT_EQ(p.layers[1].scale, 2.0f);
  // GL_ADD through the combiner, keeping the previous alpha: the same as
  // GL_ADD where the texel's alpha is 1 (texture 8 is opaque).
  Game a = two_units([](Game& u) {
    env(u, "GL_TEXTURE_ENV_MODE", 0x2200, "GL_COMBINE", 0x8570);
    env(u, "GL_COMBINE_RGB", 0x8571, "GL_ADD", 0x0104);
    env(u, "GL_COMBINE_ALPHA", 0x8572, "GL_REPLACE", 0x1E01);
    env(u, "GL_SRC0_ALPHA", 0x8588, "GL_PREVIOUS", 0x8578);
  });
  a.swap();
  const Scene sa = a.import();
  const Pass& pa = sa.pass_of(sa.draws(0)[0]);
  ASSERT_EQ(pa.layers.size(), 2u);
  EXPECT_EQ(pa.layers[1].combine, Combine::add);
  EXPECT_EQ(pa.layers[1].scale, 1.0f);
}

TEST(GlTrace, ACombineOovrsLayersCannotComputeIsRefusedAtTheDraw) {
  {
    // A scaled sum: OpenGL scales texel + previous, oovr the texel alone.
    Game g = two_units([](Game& u) {
      env(u, "GL_TEXTURE_ENV_MODE", 0x2200, "GL_COMBINE", 0x8570);
      env(u, "GL_COMBINE_RGB", 0x8571, "GL_ADD", 0x0104);
      rgb_scale(u, 2);
    });
    expect_refused(g, "an RGB scale on a sum or a replacement");
  }
  {
    // A scale on unit 0 with unit 1 after it: OpenGL clamps between units.
    Game g;
    g.enable("GL_TEXTURE_2D", 0x0DE1);
    env(g, "GL_TEXTURE_ENV_MODE", 0x2200, "GL_COMBINE", 0x8570);
    rgb_scale(g, 2);
    second_unit(g);
    g.perspective();
    g.quad(-5);
    expect_refused(g, "an RGB scale on a unit before another");
  }
  {
    // Interpolation with a constant colour.
    Game g = two_units([](Game& u) {
      env(u, "GL_TEXTURE_ENV_MODE", 0x2200, "GL_COMBINE", 0x8570);
      env(u, "GL_COMBINE_RGB", 0x8571, "GL_INTERPOLATE", 0x8575);
    });
    expect_refused(g, "functions or sources other than the texel and the previous colour");
  }
  {
    // The previous alpha kept over a texel whose alpha is not 1 (texture 7 on unit 0 alone).
    Game g;
    g.enable("GL_TEXTURE_2D", 0x0DE1);
    env(g, "GL_TEXTURE_ENV_MODE", 0x2200, "GL_COMBINE", 0x8570);
    env(g, "GL_COMBINE_ALPHA", 0x8572, "GL_REPLACE", 0x1E01);
    env(g, "GL_SRC0_ALPHA", 0x8588, "GL_PRIMARY_COLOR", 0x8577);
    g.perspective();
    g.quad(-5);
    expect_refused(g, "an alpha function unlike its colour function's");
  }
  {
    Game g;
    g.w.call("glTexEnvf",
             {{"target", g.w.e("GL_TEXTURE_ENV", 0x2300)}, {"pname", g.w.e("GL_TEXTURE_LOD_BIAS", 0x8501)}, {"param", g.w.f(1)}});
    g.perspective();
    g.quad(-5);
    expect_refused(g, "texture environment parameter 34049");
  }
}

// A DarkPlaces-like OpenGL 3 frame: a program of one permutation (its
// defines in their own source strings, the shader body last), attributes
// bound by name, a stream vertex buffer and an element buffer, the
// projection as one matrix uniform; drawn into a framebuffer object whose
// texture a generic program then copies into the window.
class Gl3Game {
 public:
  TraceWriter w;
  Gl3Game() { w.gl_viewport(64, 48); }

  void quad(float z) { w.gl_buffer_quad(z); }
  void swap() { w.call("glXSwapBuffers", {{"dpy", w.opaque(1)}, {"drawable", w.u(2)}}); }
  Scene import() const {
    GlTraceWindow win;
    win.count = 1;
    return import_gl_trace_bytes(w.finish(), "game.trace", win);
  }
};

// A perspective projection (90 degrees, near 1, far 100) times a rotation
// about the view axis by 90 degrees and a translation: what a game's camera makes.
std::vector<float> camera_mvp(Mat4& p, Mat4& mv) {
  p = Mat4{};
  p.at(2, 2) = -101.0f / 99;
  p.at(2, 3) = -200.0f / 99;
  p.at(3, 2) = -1;
  p.at(3, 3) = 0;
  mv = rotate({0, 0, 1}, radians(90.0f)) * translate({0, 0, -3});
  const Mat4 mvp = p * mv;
  std::vector<float> out;
  for (int k = 0; k < 16; ++k) out.push_back(mvp.m[k / 4][k % 4]);
  return out;
}

TEST(GlTrace, AProgramsDrawTakesItsPositionsFromItsMatrixUniformAndItsPassFromItsPermutation) {
  Gl3Game g;
  g.w.gl_texture_2x2(7, {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255});
  g.w.gl_program(5, {"MODE_GENERIC", "USEDIFFUSE", "USEVIEWTINT"});     // USEVIEWTINT: the vertex colour, in a generic program
  g.w.call("glUniform1i", {{"location", g.w.i(1)}, {"v0", g.w.i(0)}});  // Texture_First on unit 0
  Mat4 p, mv;
  g.w.gl_uniform_matrix(camera_mvp(p, mv));
  g.quad(-5);
  g.swap();
  const Scene s = g.import();
  ASSERT_EQ(s.draws(0).size(), 1u);
  const Object& o = s.draws(0)[0];
  EXPECT_EQ(o.view, DrawView::captured);
  // The matrix uniform factors back into the camera's projection and placement.
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      EXPECT_NEAR(o.clip_from_eye.at(r, c), p.at(r, c), 1e-5) << r << "," << c;
      EXPECT_NEAR(o.world_from_object.at(r, c), mv.at(r, c), 1e-5) << r << "," << c;
    }
  const Mesh& m = s.meshes[size_t(o.mesh)];
  ASSERT_EQ(m.vertices.size(), 4u);
  EXPECT_EQ(m.vertices[2].position.x, 1.0f);
  EXPECT_EQ(m.vertices[2].position.z, -5.0f);
  EXPECT_EQ(m.vertices[2].uv.y, 1.0f);
  ASSERT_EQ(m.colours.size(), 4u);  // the disabled colour attribute's constant
  EXPECT_EQ(m.colours[0], 0xFFFF80FFu);
  const Pass& pass = s.pass_of(o);
  // Texture_First combined; Texture_Color, which this program kept (it has
  // a location) though a generic permutation does not combine it, fetched.
  ASSERT_EQ(pass.layers.size(), 2u);
  EXPECT_EQ(pass.layers[0].combine, Combine::modulate);
  EXPECT_EQ(s.textures[size_t(pass.layers[0].texture)].width(), 2);
  EXPECT_EQ(pass.layers[1].combine, Combine::fetch);

  // A fetch layer is sampled (counted) and changes no pixel.
  StereoRig rig;
  rig.eye_width = 64;
  rig.eye_height = 48;
  const StereoView view = make_stereo_view(s.camera, 0, rig);
  const FrameOutput with = render_frame(s, view, PipelineSettings{}, 0);
  Scene without = s;
  without.materials[size_t(o.material)].passes[size_t(o.pass)].layers.pop_back();
  const FrameOutput plain = render_frame(without, view, PipelineSettings{}, 0);
  ASSERT_GT(plain.trace.total_passed(), 0u);
  EXPECT_EQ(with.colour.rgba, plain.colour.rgba);
  EXPECT_EQ(with.trace.layer_fetches(), 2 * plain.trace.layer_fetches());
}

TEST(GlTrace, TheViewRenderedIntoATextureAndCopiedIntoTheWindowIsTheViewsDraws) {
  Gl3Game g;
  g.w.gl_texture_2x2(7, {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255});
  // The view's target: texture 9 on framebuffer 3.
  g.w.call("glBindTexture", {{"target", g.w.e("GL_TEXTURE_2D", 0x0DE1)}, {"texture", g.w.u(9)}});
  g.w.call("glBindFramebuffer", {{"target", g.w.e("GL_FRAMEBUFFER", 0x8D40)}, {"framebuffer", g.w.u(3)}});
  g.w.call("glFramebufferTexture2D", {{"target", g.w.e("GL_FRAMEBUFFER", 0x8D40)},
                                      {"attachment", g.w.e("GL_COLOR_ATTACHMENT0", 0x8CE0)},
                                      {"textarget", g.w.e("GL_TEXTURE_2D", 0x0DE1)},
                                      {"texture", g.w.u(9)},
                                      {"level", g.w.i(0)}});
  g.w.call("glBindTexture", {{"target", g.w.e("GL_TEXTURE_2D", 0x0DE1)}, {"texture", g.w.u(7)}});
  g.w.gl_program(5, {"MODE_LIGHTMAP", "USEALPHAKILL"});
  Mat4 p, mv;
  g.w.gl_uniform_matrix(camera_mvp(p, mv));
  g.w.call("glUniform1i", {{"location", g.w.i(2)}, {"v0", g.w.i(0)}});  // Texture_Color
  g.w.call("glUniform3f", {{"location", g.w.i(3)}, {"v0", g.w.f(0.5f)}, {"v1", g.w.f(0.25f)}, {"v2", g.w.f(1)}});
  g.w.call("glUniform1f", {{"location", g.w.i(4)}, {"v0", g.w.f(0.75f)}});
  g.quad(-5);
  // The copy into the window: a generic program sampling texture 9.
  g.w.call("glBindFramebuffer", {{"target", g.w.e("GL_FRAMEBUFFER", 0x8D40)}, {"framebuffer", g.w.u(0)}});
  g.w.gl_program(6, {"MODE_GENERIC", "USEDIFFUSE"});
  g.w.gl_uniform_matrix({2.0f / 64, 0, 0, 0, 0, -2.0f / 48, 0, 0, 0, 0, -1, 0, -1, 1, 0, 1});
  g.w.call("glUniform1i", {{"location", g.w.i(1)}, {"v0", g.w.i(0)}});
  g.w.call("glBindTexture", {{"target", g.w.e("GL_TEXTURE_2D", 0x0DE1)}, {"texture", g.w.u(9)}});
  g.quad(0);
  g.swap();
  const Scene s = g.import();
  ASSERT_EQ(s.draws(0).size(), 1u);  // the copy is not a draw of its own
  const Pass& pass = s.pass_of(s.draws(0)[0]);
  // MODE_LIGHTMAP without a lightmap bound: Texture_Color x Color_Diffuse, alpha x Alpha.
  EXPECT_FLOAT_EQ(pass.colour.x, 0.5f);
  EXPECT_FLOAT_EQ(pass.colour.y, 0.25f);
  EXPECT_FLOAT_EQ(pass.colour.w, 0.75f);
  EXPECT_EQ(pass.alpha_func, AlphaFunc::gequal);
  bool noted = false;
  for (const auto& n : s.notes) noted = noted || n.find("copied the view") != std::string::npos;
  EXPECT_TRUE(noted);
}

TEST(GlTrace, AProgramsPermutationOovrDoesNotDrawIsRefusedAtItsDraw) {
  for (const std::vector<std::string>& defines : {std::vector<std::string>{"MODE_WATER"},
                                                  {"MODE_LIGHTMAP", "USEFOGOUTSIDE"},
                                                  {"MODE_GENERIC", "USEDIFFUSE", "USEGAMMARAMPS"}}) {
    Gl3Game g;
    g.w.gl_program(5, defines);
    Mat4 p, mv;
    g.w.gl_uniform_matrix(camera_mvp(p, mv));
    g.quad(-5);
    expect_refused(g, {"a draw through DarkPlaces' " + defines.front() + " programs", defines.back()});
  }
  // A skewed matrix is no camera: refused, not mis-projected.
  Gl3Game g;
  g.w.gl_program(5, {"MODE_GENERIC"});
  g.w.gl_uniform_matrix({1, 0, 0, 0, 0.5f, 1, 0, 0, 0, 0, -1, -1, 0, 0, -2, 0});
  g.quad(-5);
  g.swap();
  EXPECT_THROW(g.import(), Error);
}

// ioquake3's opengl2 renderer: its lightall program on the fast light path
// with a lightmap is diffuse x var_Color x lightmap, var_Color = u_VertColor
// x attr_Color + u_BaseColor (here 2 x the disabled colour attribute's
// constant: above 1, as the world's u_BaseColor 2 of the map's overbright
// bits is); u_AlphaTest 3 keeps alpha >= 0.5.
TEST(GlTrace, AnIoquake3ProgramsVertexStageIsEvaluatedAndItsFragmentStageIsItsTextures) {
  Gl3Game g;
  g.w.gl_texture_2x2(7, {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255});
  g.w.call("glActiveTexture", {{"texture", g.w.e("GL_TEXTURE1", 0x84C1)}});
  g.w.gl_texture_2x2(8, {128, 128, 128, 255, 64, 64, 64, 255, 32, 32, 32, 255, 16, 16, 16, 255});
  g.w.call("glActiveTexture", {{"texture", g.w.e("GL_TEXTURE0", 0x84C0)}});
  g.w.gl_ioq3_program(5, "lightall", {"USE_LIGHT", "USE_FAST_LIGHT", "USE_LIGHTMAP", "GLOSS_IS_SMOOTHNESS"});
  g.w.call("glUniform1i", {{"location", g.w.i(1)}, {"v0", g.w.i(0)}});  // u_DiffuseMap on unit 0
  g.w.call("glUniform1i", {{"location", g.w.i(2)}, {"v0", g.w.i(1)}});  // u_LightMap on unit 1
  g.w.gl_uniform4f(3, 0, 0, 0, 0);                                      // u_BaseColor
  g.w.gl_uniform4f(4, 2, 2, 2, 1);                                      // u_VertColor
  g.w.call("glUniform1i", {{"location", g.w.i(5)}, {"v0", g.w.i(3)}});  // u_AlphaTest
  Mat4 p, mv;
  g.w.gl_uniform_matrix(camera_mvp(p, mv));
  g.quad(-5);  // attr_Color: the constant (1, 0.5, 1, 1); attr_TexCoord0: the quad's
  g.swap();
  const Scene s = g.import();
  ASSERT_EQ(s.draws(0).size(), 1u);
  const Object& o = s.draws(0)[0];
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(o.clip_from_eye.at(r, c), p.at(r, c), 1e-5) << r << "," << c;
  const Pass& pass = s.pass_of(o);
  ASSERT_EQ(pass.layers.size(), 2u);
  EXPECT_EQ(pass.layers[0].combine, Combine::modulate);
  EXPECT_EQ(pass.layers[0].coords, TexCoords::surface);
  EXPECT_EQ(pass.layers[1].combine, Combine::modulate);
  EXPECT_EQ(pass.layers[1].coords, TexCoords::lightmap);
  EXPECT_EQ(s.textures[size_t(pass.layers[1].texture)].levels[0].rgba[0], 128);
  // Every vertex has the same colour: it is the pass colour, overbright kept.
  EXPECT_FLOAT_EQ(pass.colour.x, 2.0f);
  EXPECT_FLOAT_EQ(pass.colour.y, 1.0f);
  EXPECT_FLOAT_EQ(pass.colour.z, 2.0f);
  EXPECT_FLOAT_EQ(pass.colour.w, 1.0f);
  EXPECT_EQ(pass.alpha_func, AlphaFunc::gequal);
  EXPECT_FLOAT_EQ(pass.alpha_ref, 0.5f);
  const Mesh& m = s.meshes[size_t(o.mesh)];
  ASSERT_EQ(m.vertices.size(), 4u);
  EXPECT_EQ(m.vertices[2].uv.x, 1.0f);
  EXPECT_EQ(m.vertices[2].position.z, -5.0f);
}

// A vertex array object holds its attributes and element buffer: a draw
// after binding one back draws what it holds; a draw with a new one, which
// holds no element buffer, is refused.
TEST(GlTrace, EachVertexArrayObjectKeepsItsOwnAttributesAndElementBuffer) {
  const auto game = [](bool second_draws) {
    auto g = std::make_unique<Gl3Game>();
    g->w.gl_texture_2x2(7, {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255});
    g->w.gl_ioq3_program(5, "generic", {});
    g->w.gl_uniform4f(3, 0.25f, 0.5f, 0.75f, 1);  // u_BaseColor
    Mat4 p, mv;
    g->w.gl_uniform_matrix(camera_mvp(p, mv));
    g->w.call("glBindVertexArray", {{"array", g->w.u(1)}});
    g->quad(-5);
    g->w.call("glBindVertexArray", {{"array", g->w.u(2)}});
    if (second_draws) g->w.call("glBindVertexArray", {{"array", g->w.u(1)}});
    g->w.call("glDrawElements", {{"mode", g->w.e("GL_TRIANGLES", 4)},
                                 {"count", g->w.i(6)},
                                 {"type", g->w.e("GL_UNSIGNED_SHORT", 0x1403)},
                                 {"indices", g->w.u(32)}});
    g->swap();
    return g;
  };
  const Scene s = game(true)->import();
  ASSERT_EQ(s.draws(0).size(), 2u);
  EXPECT_EQ(s.draws(0)[0].mesh, s.draws(0)[1].mesh);
  // u_VertColor unset (0): the colour is u_BaseColor.
  EXPECT_FLOAT_EQ(s.pass_of(s.draws(0)[1]).colour.y, 0.5f);
  try {
    game(false)->import();
    ADD_FAILURE() << "a draw with an empty vertex array object accepted";
  } catch (const Error& e) {
    // The element buffer binding is the object's: the new one has none.
    EXPECT_NE(std::string(e.what()).find("indices neither in a buffer object nor recorded"), std::string::npos) << e.what();
  }
}

TEST(GlTrace, AnIoquake3ProgramOovrDoesNotDrawIsRefusedAtItsDraw) {
  const std::vector<std::pair<std::string, std::vector<std::string>>> programs = {
      {"lightall", {"USE_LIGHT", "USE_LIGHTMAP", "USE_NORMALMAP"}},  // per-pixel lighting
      {"lightall", {"USE_LIGHT", "USE_FAST_LIGHT", "USE_SHADOWMAP"}},
      {"generic", {"USE_BONE_ANIMATION"}},
      {"tonemap", {}}};
  for (const auto& [shader, defines] : programs) {
    Gl3Game g;
    g.w.gl_ioq3_program(5, shader, defines);
    Mat4 p, mv;
    g.w.gl_uniform_matrix(camera_mvp(p, mv));
    g.quad(-5);
    // Per-pixel lighting is refused as such, a define by its name, another
    // shader as one.
    const std::string named = defines.empty()                     ? "other than its generic, lightall and dlight shaders"
                              : defines.back() == "USE_NORMALMAP" ? "without USE_FAST_LIGHT"
                                                                  : "with " + defines.back();
    expect_refused(g, {"a draw through ioquake3's", named});
  }
}

// An attribute bound beyond the 16 kept is an Error at the bind (fuzz_apitrace
// found it reaching a draw as std::out_of_range).
TEST(GlTrace, AnAttributeBoundBeyondTheSixteenKeptIsAnError) {
  Gl3Game g;
  g.w.gl_program(5, {"MODE_GENERIC"});
  g.w.call("glBindAttribLocation", {{"program", g.w.u(5)}, {"index", g.w.u(64)}, {"name", g.w.str("Attrib_Position")}});
  expect_refused(g, "vertex attribute 64");
}

// ioquake3's vertex stages, one vertex at a time, against their GLSL
// worked by hand.
TEST(Ioq3Vertex, KeyFramesTexCoordModsLightsAndDlightsAreTheGlslsArithmetic) {
  Ioq3Stage st;  // ioquake3's constants (DGEN_WAVE_SIN 1, TCGEN_LIGHTMAP 2, ...) by default
  Ioq3VertexIn in;
  in.position = {10, 20, 30};
  in.position2 = {20, 20, 30};
  in.normal = {0, 0, 1};
  in.normal2 = {0, 0, 1};
  in.colour = {0.5f, 0.5f, 0.5f, 1};
  in.tex0 = {0.25f, 0.5f};
  in.tex1 = {0.75f, 0.125f};
  Ioq3Uniforms u;
  u.vert_colour = {1, 1, 1, 1};
  u.base_colour = {0.25f, 0, 0, 0};
  // Key frames: mix(attr_Position, attr_Position2, u_VertexLerp).
  st.vertex_animation = true;
  u.vertex_lerp = 0.25f;
  Ioq3VertexOut out = ioq3_vertex(st, u, in);
  EXPECT_FLOAT_EQ(out.position.x, 12.5f);
  EXPECT_FLOAT_EQ(out.colour[0], 0.75f);  // 1 x 0.5 + 0.25
  EXPECT_FLOAT_EQ(out.colour[1], 0.5f);
  EXPECT_FLOAT_EQ(out.uv.x, 0.25f);
  EXPECT_FLOAT_EQ(out.lightmap.y, 0.125f);
  // A deform: base + sin(2 pi (phase + spread x (x+y+z) + time x frequency)) x amplitude along the normal.
  st.vertex_animation = false;
  st.deform = true;
  u.deform_gen = 1;
  u.deform_params = {1, 2, 0.125f, 0.5f, 0};  // base, amplitude, phase, frequency, spread
  u.time = 0.25f;
  out = ioq3_vertex(st, u, in);
  EXPECT_NEAR(out.position.z, 30 + 1 + 2 * std::sin(2 * kPi * 0.25f), 1e-5);
  // A texture-coordinate map: the affine part and a turbulence of amplitude 0.
  st.deform = false;
  st.tcmod = true;
  u.tex_matrix = {2, 0, 0, 3};
  u.off_turb = {0.5f, 0.25f, 0, 0};
  out = ioq3_vertex(st, u, in);
  EXPECT_FLOAT_EQ(out.uv.x, 0.25f * 2 + 0.5f);
  EXPECT_FLOAT_EQ(out.uv.y, 0.5f * 3 + 0.25f);
  // TCGEN_LIGHTMAP takes the lightmap's coordinates.
  st.tcgen = true;
  u.tcgen = 2;
  u.tex_matrix = {1, 0, 0, 1};
  u.off_turb = {};
  out = ioq3_vertex(st, u, in);
  EXPECT_FLOAT_EQ(out.uv.x, 0.75f);
  // The fast light: a point light 10 units above, radius 20: N.L = 1,
  // attenuation clamp((0.5 x 400/100 - 1.5) x 1 + 1) = 1.
  st.tcgen = st.tcmod = false;
  st.light_vector = true;
  u.light_origin = {10, 20, 40, 1};
  u.light_radius = 20;
  u.directed_light = {0.5f, 0.5f, 0.5f};
  u.ambient_light = {0.25f, 0.25f, 0.25f};
  out = ioq3_vertex(st, u, in);
  EXPECT_FLOAT_EQ(out.colour[1], 0.5f * (0.5f + 0.25f));
  // Radius 10: attenuation clamp((0.5 x 1 - 1.5) + 1) = 0, the ambient alone.
  u.light_radius = 10;
  out = ioq3_vertex(st, u, in);
  EXPECT_FLOAT_EQ(out.colour[1], 0.5f * 0.25f);
  // A dynamic light's disc: coordinates from the distance x 1/radius, the
  // colour where the surface faces the light.
  Ioq3Stage dl = st;
  dl.shader = Ioq3Stage::Shader::dlight;
  dl.light_vector = false;
  u.dlight_info = {14, 20, 32, 0.125f};
  u.colour = {1, 0.5f, 0.25f, 1};
  out = ioq3_vertex(dl, u, in);
  EXPECT_FLOAT_EQ(out.uv.x, 4 * 0.125f + 0.5f);
  EXPECT_FLOAT_EQ(out.uv.y, 0.5f);
  EXPECT_FLOAT_EQ(out.colour[1], 0.5f * std::clamp(2 * (1 - 2 * 0.125f), 0.0f, 1.0f));
  u.dlight_info = {14, 20, 28, 0.125f};  // below the surface: dark
  EXPECT_FLOAT_EQ(ioq3_vertex(dl, u, in).colour[0], 0.0f);
}

}  // namespace
}  // namespace oovr
