// Materials with layers and passes: blending, alpha functions, depth state,
// texture-coordinate transforms, what the trace records of them, their
// fragment cost and the texture storage formats.
#include <gtest/gtest.h>

#include <cmath>

#include "oovr/core/error.h"
#include "oovr/pipeline/pipeline.h"
#include "oovr/pipeline/shader_cost.h"
#include "oovr/pipeline/tiled_layout.h"
#include "oovr/scene/scene.h"
#include "test_util.h"

namespace oovr {
namespace {

// A 16x16 frame covered by one quad (two triangles) drawn with `material`'s
// passes; every pixel's colour comes from the passes alone.
Scene quad_scene(Material material) {
  Scene s = test::triangle_scene({{0, 0}, {16, 0}, {16, 16}, {0, 16}}, {0, 1, 2, 0, 2, 3});
  s.materials = {std::move(material)};
  s.objects.clear();
  s.add_draws("quad", 0, 0, Mat4::identity());
  return s;
}

Texture solid(uint8_t r, uint8_t g, uint8_t b, uint8_t a, int size = 4) {
  std::vector<uint8_t> px(size_t(size) * size * 4);
  for (size_t i = 0; i < px.size(); i += 4) {
    px[i] = r;
    px[i + 1] = g;
    px[i + 2] = b;
    px[i + 3] = a;
  }
  return make_texture("solid", "solid", size, size, std::move(px));
}

Pass flat(Vec4 colour) {
  Pass p;
  p.colour = colour;
  return p;
}

const uint8_t* centre(const FrameOutput& out) { return out.colour.pixel(8, 8); }

TEST(Materials, AddDrawsMakesOneObjectPerPassEachAfterTheLast) {
  Material m;
  m.name = "three";
  m.passes = {flat({1, 0, 0, 1}), flat({0, 1, 0, 1}), flat({0, 0, 1, 1})};
  const Scene s = quad_scene(m);
  ASSERT_EQ(s.objects.size(), 3u);
  for (int p = 0; p < 3; ++p) EXPECT_EQ(s.objects[size_t(p)].pass, p);
  EXPECT_TRUE(s.objects[0].after.empty());
  EXPECT_EQ(s.objects[1].after, std::vector<uint32_t>{0});
  EXPECT_EQ(s.objects[2].after, std::vector<uint32_t>{1});
  s.validate();
}

TEST(Materials, ValidateRejectsAPassOrLayerThatDoesNotExist) {
  Scene s = quad_scene(Material::textured("m", -1));
  s.objects[0].pass = 1;
  EXPECT_THROW(s.validate(), Error);
  s.objects[0].pass = 0;
  s.materials[0].pass().layers.push_back({LayerKind::glow, 3, TexCoords::surface, Combine::add, 1.0f, {}});
  EXPECT_THROW(s.validate(), Error);
  s.materials[0].passes.clear();
  EXPECT_THROW(s.validate(), Error);
}

TEST(Materials, AdditiveAndFilterBlendsCombineWithTheFrame) {
  Material m;
  m.name = "blend";
  Pass base = flat({0.25f, 0.5f, 0.125f, 1});
  Pass add = flat({0.25f, 0.25f, 0.25f, 1});
  add.src = add.dst = BlendFactor::one;  // GL_ONE GL_ONE
  add.depth_func = DepthFunc::lequal;    // same surface: equal depths pass
  add.depth_write = false;
  Pass filter = flat({0.5f, 0.5f, 0.5f, 1});
  filter.src = BlendFactor::dst_colour;  // GL_DST_COLOR GL_ZERO: frame x colour
  filter.dst = BlendFactor::zero;
  filter.depth_func = DepthFunc::lequal;
  filter.depth_write = false;
  m.passes = {base, add, filter};
  const FrameOutput out = render_frame(quad_scene(m), test::ortho_view(16, 16), test::exact_settings());
  // (0.25 + 0.25) * 0.5 = 0.25, (0.5 + 0.25) * 0.5 = 0.375, (0.125 + 0.25) * 0.5 = 0.1875.
  EXPECT_NEAR(centre(out)[0], 0.25 * 255, 1.5);
  EXPECT_NEAR(centre(out)[1], 0.375 * 255, 1.5);
  EXPECT_NEAR(centre(out)[2], 0.1875 * 255, 1.5);
  // The trace: the first pass writes colour and depth and reads no colour;
  // the blended passes read and write colour and write no depth.
  ASSERT_FALSE(out.trace.tiles.empty());
  for (const TileWork& w : out.trace.tiles) {
    EXPECT_EQ(w.passed, 256u);
    EXPECT_NE(w.colour_write_mask, 0u);
    if (w.object == 0) {
      EXPECT_EQ(w.colour_read_mask, 0u);
      EXPECT_EQ(w.depth_write_mask, w.colour_write_mask);
    } else {
      EXPECT_EQ(w.colour_read_mask, w.colour_write_mask);
      EXPECT_EQ(w.depth_write_mask, 0u);
    }
  }
}

TEST(Materials, ALaterPassWithDepthLessFailsOnItsOwnSurface) {
  // The reason multi-pass engines draw with GL_LEQUAL: equal depths fail GL_LESS.
  Material m;
  m.name = "less";
  m.passes = {flat({1, 0, 0, 1}), flat({0, 1, 0, 1})};
  const FrameOutput out = render_frame(quad_scene(m), test::ortho_view(16, 16), test::exact_settings());
  EXPECT_EQ(centre(out)[0], 255);
  EXPECT_EQ(centre(out)[1], 0);
  uint64_t second = 0;
  for (const TileWork& w : out.trace.tiles)
    if (w.object == 1) second += w.passed;
  EXPECT_EQ(second, 0u);
}

TEST(Materials, AlphaFunctionsKeepWhatTheyShould) {
  for (const auto& [func, alpha, kept] : std::vector<std::tuple<AlphaFunc, uint8_t, bool>>{{AlphaFunc::greater, 0, false},
                                                                                           {AlphaFunc::greater, 1, true},
                                                                                           {AlphaFunc::less, 100, true},
                                                                                           {AlphaFunc::less, 200, false},
                                                                                           {AlphaFunc::gequal, 128, true},
                                                                                           {AlphaFunc::gequal, 100, false}}) {
    Scene s = quad_scene(Material::textured("a", 0));
    s.textures = {solid(200, 200, 200, alpha)};
    s.materials[0].pass().alpha_func = func;
    s.materials[0].pass().alpha_ref = func == AlphaFunc::greater ? 0.0f : 0.5f;
    const FrameOutput out = render_frame(s, test::ortho_view(16, 16), test::exact_settings());
    EXPECT_EQ(out.trace.total_passed(), kept ? 256u : 0u) << int(func) << " " << int(alpha);
  }
}

TEST(Materials, LayersModulateOrAddWithTheirScale) {
  Scene s = quad_scene(Material::textured("m", 0, 1, 2.0f));  // diffuse x lightmap x 2
  s.textures = {solid(200, 100, 50, 255), solid(64, 128, 255, 255)};
  FrameOutput out = render_frame(s, test::ortho_view(16, 16), test::exact_settings());
  EXPECT_NEAR(centre(out)[0], 200 * 64 / 255.0 * 2, 1.0);
  EXPECT_NEAR(centre(out)[1], 100 * 128 / 255.0 * 2, 1.0);
  EXPECT_EQ(centre(out)[2], 100);  // 50 x 1 x 2
  s.materials[0].pass().layers[1].combine = Combine::add;
  s.materials[0].pass().layers[1].scale = 0.5f;
  out = render_frame(s, test::ortho_view(16, 16), test::exact_settings());
  EXPECT_NEAR(centre(out)[0], 200 + 32, 1.0);
  EXPECT_NEAR(centre(out)[1], 100 + 64, 1.0);
  EXPECT_NEAR(centre(out)[2], 50 + 127.5, 1.0);
}

TEST(Materials, TexModsScaleThenScrollWithTheFrameTime) {
  TextureLayer l{LayerKind::diffuse, 0, TexCoords::surface, Combine::modulate, 1.0f, {}};
  l.mods = {{TexMod::Kind::scale, 2, 4}, {TexMod::Kind::scroll, 0.25f, -0.5f}};
  const UvTransform at0 = l.transform(0);
  EXPECT_FLOAT_EQ(at0.a, 2);
  EXPECT_FLOAT_EQ(at0.e, 4);
  EXPECT_FLOAT_EQ(at0.c, 0);
  const UvTransform at1 = l.transform(1.0);  // scrolled by (0.25, -0.5), wrapped to [0, 1)
  EXPECT_FLOAT_EQ(at1.c, 0.25f);
  EXPECT_FLOAT_EQ(at1.f, 0.5f);
  // Scroll before scale: the offset is scaled too.
  l.mods = {{TexMod::Kind::scroll, 0.25f, 0}, {TexMod::Kind::scale, 2, 1}};
  EXPECT_FLOAT_EQ(l.transform(1.0).c, 0.5f);

  // A scrolling stripe texture moves on screen from frame to frame.
  std::vector<uint8_t> px(16 * 16 * 4, 255);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 8; ++x) px[size_t(y * 16 + x) * 4] = 0;  // left half: no red
  Scene s = quad_scene(Material::textured("scroll", 0));
  s.textures = {make_texture("stripes", "stripes", 16, 16, std::move(px), Wrap::repeat, false)};
  for (int i = 0; i < 4; ++i)
    s.meshes[0].vertices[size_t(i)].uv = {s.meshes[0].vertices[size_t(i)].position.x / 16,
                                          s.meshes[0].vertices[size_t(i)].position.y / 16};
  s.materials[0].pass().layers[0].mods = {{TexMod::Kind::scroll, 0.5f, 0}};
  s.camera.frames.resize(61);
  const FrameOutput f0 = render_frame(s, test::ortho_view(16, 16), test::exact_settings(), 0);
  const FrameOutput f60 = render_frame(s, test::ortho_view(16, 16), test::exact_settings(), 60);  // 1 s: half a turn
  EXPECT_LT(f0.colour.pixel(2, 8)[0], 10);
  EXPECT_GT(f60.colour.pixel(2, 8)[0], 245);
}

TEST(Materials, FragmentCostCountsLayersAndOperations) {
  using C = FragmentCosts;
  const uint32_t bare = C::setup + C::output;
  EXPECT_EQ(fragment_instructions(Pass{}), bare);
  EXPECT_EQ(fragment_instructions(Pass::textured(0)), bare + C::coordinates + C::lookup);
  // Diffuse x lightmap x 2: two lookups, one modulate, one scale.
  EXPECT_EQ(fragment_instructions(Pass::textured(0, 1, 2.0f)), bare + 2 * (C::coordinates + C::lookup) + C::combine + C::scale);
  Pass p = Pass::textured(0);
  p.alpha_func = AlphaFunc::gequal;
  p.colour = {0.5f, 1, 1, 1};
  p.layers[0].mods = {{TexMod::Kind::scroll, 0.1f, 0}};
  EXPECT_EQ(fragment_instructions(p), bare + C::coordinates + C::lookup + C::transform + C::colour + C::alpha_test);
  // A captured program's fetch-only layers: their lookups, no combine, and
  // what the program computes with a normal or gloss map.
  Pass f = Pass::textured(0);
  f.layers.push_back({LayerKind::normal, 1, TexCoords::surface, Combine::fetch, 1.0f, {}});
  f.layers.push_back({LayerKind::gloss, 1, TexCoords::surface, Combine::fetch, 1.0f, {}});
  f.layers.push_back({LayerKind::diffuse, 1, TexCoords::surface, Combine::fetch, 1.0f, {}});
  EXPECT_EQ(fragment_instructions(f),
            bare + 4 * (C::coordinates + C::lookup) + C::surface_normal + C::diffuse_light + C::specular);
  // The trace carries each draw's cost; blending itself costs no instruction.
  Material m;
  m.name = "two";
  m.passes = {Pass::textured(0, 1, 2.0f), Pass::textured(0)};
  m.passes[1].src = m.passes[1].dst = BlendFactor::one;
  Scene s = quad_scene(m);
  s.textures = {solid(1, 2, 3, 255), solid(4, 5, 6, 255)};
  const FrameOutput out = render_frame(s, test::ortho_view(16, 16), test::exact_settings());
  EXPECT_EQ(out.trace.objects[0].fragment_instructions, fragment_instructions(m.passes[0]));
  EXPECT_EQ(out.trace.objects[1].fragment_instructions, fragment_instructions(m.passes[1]));
  EXPECT_EQ(out.trace.objects[0].texture_layers, 2u);
  EXPECT_EQ(out.trace.objects[1].texture_layers, 1u);
}

TEST(Materials, BlockCompressedFormatsHoldMoreTexelsPerLine) {
  Texture opaque = solid(10, 20, 30, 255, 256);
  Texture alpha = solid(10, 20, 30, 128, 256);
  Texture lightmap = solid(10, 20, 30, 255, 256);
  lightmap.compress = false;
  EXPECT_TRUE(opaque.opaque);
  EXPECT_FALSE(alpha.opaque);
  const auto lines = [](const Texture& t, TextureFormat f) {  // of the base level
    int w = 0, h = 0;
    texture_line_shape(t, f, 128, w, h);
    return texture_layout(t, w, h).first_line[1];
  };
  const auto shape = [](const Texture& t, TextureFormat f, uint32_t line) {
    int w = 0, h = 0;
    texture_line_shape(t, f, line, w, h);
    return std::make_pair(w, h);
  };
  // 128-byte lines: RGBA8 8x4 texels, BC1 16 blocks = 16x16, BC3 8 blocks = 16x8.
  EXPECT_EQ(shape(opaque, TextureFormat::rgba8, 128), std::make_pair(8, 4));
  EXPECT_EQ(shape(opaque, TextureFormat::bc1, 128), std::make_pair(16, 16));
  EXPECT_EQ(shape(opaque, TextureFormat::bc3, 128), std::make_pair(16, 8));
  EXPECT_EQ(shape(opaque, TextureFormat::bc1, 32), std::make_pair(8, 8));
  // The games' rule: BC1 when opaque, BC3 with alpha, lightmaps uncompressed.
  EXPECT_EQ(shape(opaque, TextureFormat::bc, 128), std::make_pair(16, 16));
  EXPECT_EQ(shape(alpha, TextureFormat::bc, 128), std::make_pair(16, 8));
  EXPECT_EQ(shape(lightmap, TextureFormat::bc, 128), std::make_pair(8, 4));
  // Base level of 256x256: 8192 lines in RGBA8, 256 in BC1 (8x fewer bytes), 512 in BC3.
  EXPECT_EQ(lines(opaque, TextureFormat::rgba8) / lines(opaque, TextureFormat::bc1), 8u);
  EXPECT_EQ(lines(opaque, TextureFormat::rgba8) / lines(opaque, TextureFormat::bc3), 4u);
  EXPECT_EQ(parse_texture_format("bc"), TextureFormat::bc);
  EXPECT_THROW(parse_texture_format("dxt9"), Error);
}

TEST(Materials, TheStorageFormatChangesTrafficNotTheImage) {
  Scene s = quad_scene(Material::textured("m", 0));
  std::vector<uint8_t> px(64 * 64 * 4);
  for (size_t i = 0; i < px.size(); ++i) px[i] = uint8_t(i * 7 % 251);
  for (size_t i = 3; i < px.size(); i += 4) px[i] = 255;
  s.textures = {make_texture("noise", "noise", 64, 64, std::move(px))};
  for (auto& v : s.meshes[0].vertices) v.uv = {v.position.x / 64, v.position.y / 64};  // a texel a pixel
  PipelineSettings p = test::exact_settings();
  p.texture_format = TextureFormat::rgba8;
  const FrameOutput raw = render_frame(s, test::ortho_view(16, 16), p);
  p.texture_format = TextureFormat::bc1;
  const FrameOutput bc1 = render_frame(s, test::ortho_view(16, 16), p);
  EXPECT_EQ(raw.colour.rgba, bc1.colour.rgba);
  EXPECT_EQ(bc1.trace.texture_format, TextureFormat::bc1);
  EXPECT_LT(bc1.trace.tex_lines.size(), raw.trace.tex_lines.size());
}

// A quad lit per pixel (Shading::deluxe) over solid layers; every vertex's
// tangent frame is the world axes (S = x, T = y, N = z).
struct LitQuad {
  Scene scene;
  Pass& pass() { return scene.materials[0].pass(); }
  void add(LayerKind kind, Texture t) {
    scene.textures.push_back(std::move(t));
    const bool lm = kind == LayerKind::lightmap || kind == LayerKind::deluxe;
    pass().layers.push_back(
        {kind, int(scene.textures.size()) - 1, lm ? TexCoords::lightmap : TexCoords::surface, Combine::modulate, 1.0f, {}});
  }
  LitQuad() : scene(quad_scene(Material::textured("lit", -1))) {
    pass().shading = Shading::deluxe;
    for (auto& v : scene.meshes[0].vertices) v.uv = v.lm_uv = {v.position.x / 16, v.position.y / 16};
    scene.meshes[0].frames.assign(scene.meshes[0].vertices.size(), TangentFrame{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
    add(LayerKind::diffuse, solid(200, 100, 50, 255));
  }
  FrameOutput render() {
    scene.validate();
    StereoView v = test::ortho_view(16, 16);
    v.eye_position[0] = {8.5f, 8.5f, 100.0f};  // straight above the centre pixel
    return render_frame(scene, v, test::exact_settings());
  }
};

// The 0..255 encoding of a unit direction, as deluxe and normal maps store it.
Texture direction(Vec3 d) {
  auto enc = [](float c) { return uint8_t(std::lround((c * 0.5f + 0.5f) * 255.0f)); };
  return solid(enc(d.x), enc(d.y), enc(d.z), 255);
}

void expect_pixel(const uint8_t* px, int r, int g, int b, int tolerance) {
  EXPECT_NEAR(px[0], r, tolerance);
  EXPECT_NEAR(px[1], g, tolerance);
  EXPECT_NEAR(px[2], b, tolerance);
}

TEST(Materials, DeluxeLightingOfAFlatSurfaceIsDiffuseTimesLightmap) {
  // Without a normal map the surface normal is N: the light's cosine and
  // the division by L.z that undoes it cancel, whatever the direction
  // (DarkPlaces' MODE_LIGHTDIRECTIONMAP_MODELSPACE).
  for (const Vec3 dir : {Vec3{0, 0, 1}, Vec3{0.866f, 0, 0.5f}, Vec3{0, -0.6f, 0.8f}}) {
    LitQuad q;
    q.add(LayerKind::lightmap, solid(128, 160, 255, 255));
    q.add(LayerKind::deluxe, direction(dir));
    expect_pixel(centre(q.render()), 200 * 128 / 255, 100 * 160 / 255, 50, 1);
  }
}

TEST(Materials, ANormalMapTurnedFromTheLightDarkensIt) {
  LitQuad q;
  q.add(LayerKind::normal, direction({0.866f, 0, 0.5f}));  // 60 degrees from the light
  q.add(LayerKind::lightmap, solid(255, 255, 255, 255));
  q.add(LayerKind::deluxe, direction({0, 0, 1}));
  expect_pixel(centre(q.render()), 100, 50, 25, 2);
}

TEST(Materials, GlossAddsSpecularAndGlowAddsLight) {
  LitQuad q;
  q.add(LayerKind::gloss, solid(40, 40, 40, 255));
  q.add(LayerKind::glow, solid(10, 20, 30, 255));
  q.add(LayerKind::lightmap, solid(255, 255, 255, 255));
  q.add(LayerKind::deluxe, direction({0, 0, 1}));
  // Light and eye straight above: N.H = 1, so the full gloss colour is added.
  expect_pixel(centre(q.render()), 200 + 40 + 10, 100 + 40 + 20, 50 + 40 + 30, 2);
  // Glancing light: the highlight moves away from the eye and fades.
  q.scene.textures[4] = direction({0.866f, 0, 0.5f});
  const FrameOutput glancing = q.render();  // held: centre() points into it
  EXPECT_LT(centre(glancing)[0], 200 + 10 + 5);
}

TEST(Materials, DeluxePassesNeedTheirLayersAndFrames) {
  LitQuad q;
  q.add(LayerKind::lightmap, solid(255, 255, 255, 255));
  EXPECT_THROW(q.scene.validate(), Error) << "no deluxe layer";
  q.add(LayerKind::deluxe, direction({0, 0, 1}));
  q.scene.validate();
  q.scene.meshes[0].frames.pop_back();
  EXPECT_THROW(q.scene.validate(), Error) << "frames for some vertices only";
  q.scene.meshes[0].frames.clear();
  EXPECT_THROW(q.scene.validate(), Error) << "a lit draw of a mesh without frames";
}

TEST(Materials, TheVertexBufferHoldsTheFrames) {
  LitQuad q;
  const Mesh& m = q.scene.meshes[0];
  EXPECT_EQ(m.vertex_bytes(), m.vertices.size() * (sizeof(Vertex) + sizeof(TangentFrame)));
}

TEST(Materials, ALitPassCostsItsLightingAndEveryLayer) {
  using C = FragmentCosts;
  LitQuad q;
  q.add(LayerKind::lightmap, solid(255, 255, 255, 255));
  q.add(LayerKind::deluxe, direction({0, 0, 1}));
  const uint32_t base = C::setup + C::output + C::lit_varyings + C::light_direction + C::light_colour + C::diffuse_light;
  EXPECT_EQ(fragment_instructions(q.pass()), base + 3 * (C::coordinates + C::lookup));
  q.add(LayerKind::normal, solid(128, 128, 255, 255));
  q.add(LayerKind::gloss, solid(255, 255, 255, 255));
  q.add(LayerKind::glow, solid(0, 0, 0, 255));
  EXPECT_EQ(fragment_instructions(q.pass()), base + C::surface_normal + C::specular + C::glow + 6 * (C::coordinates + C::lookup));
}

}  // namespace
}  // namespace oovr
