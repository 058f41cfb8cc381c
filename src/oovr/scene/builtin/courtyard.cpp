// courtyard: the default scene. A colonnade of pillars that all share one
// stone texture (the paper's Figure 11 example of texture sharing), around a
// fountain with a dense bronze statue, inside brick walls with banners, on a
// lightmapped cobble floor, with crates, benches, alpha-tested trees and a
// sky dome.
// Objects differ widely in triangles, pixels and texture sets, so how work is
// balanced across GPMs matters.
#include <cmath>

#include "oovr/core/rng.h"
#include "oovr/scene/builtin.h"
#include "oovr/scene/builtin/procedural.h"

namespace oovr {
namespace {

using namespace procedural;

constexpr float kHalf = 20.0f;       // walls at +-20 m
constexpr float kColonnade = 14.0f;  // pillar ring radius
constexpr int kPillars = 16;
constexpr float kPillarRadius = 0.5f;

// Baked sun shadows of the pillars and ambient occlusion along the walls:
// values around 0.5, applied with an overbright scale of 2 as Quake 3 does.
Texture ground_lightmap(int size) {
  const float sx = 0.6f, sz = 0.8f;  // sun direction on the ground
  return texture_from(
      "courtyard-lightmap", size,
      [=](float u, float v, uint8_t* p) {
        const float x = (u - 0.5f) * 2 * kHalf, z = (0.5f - v) * 2 * kHalf;
        float light = 0.52f;
        for (int i = 0; i < kPillars; ++i) {
          const float a = 2 * kPi * float(i) / kPillars;
          const float px = kColonnade * std::sin(a), pz = kColonnade * std::cos(a);
          const float t = std::clamp((x - px) * sx + (z - pz) * sz, 0.0f, 7.0f);
          const float d = std::hypot(x - (px + sx * t), z - (pz + sz * t));
          if (d < kPillarRadius * 1.1f) light = std::min(light, 0.3f);
        }
        const float wall = kHalf - std::max(std::abs(x), std::abs(z));
        light *= 1.0f - 0.35f * std::exp(-wall * 1.5f);
        const float centre = std::hypot(x, z);
        if (centre < 3.6f && centre > 3.0f) light *= 0.75f;  // fountain rim contact shadow
        const uint8_t k = uint8_t(std::clamp(light, 0.0f, 1.0f) * 255.0f + 0.5f);
        p[0] = k;
        p[1] = uint8_t(k * 0.97f);
        p[2] = uint8_t(k * 0.9f);
        p[3] = 255;
      },
      Wrap::clamp_to_edge, /*mipmapped=*/false);
}

Mesh disc(float r, int seg, float y, float uv_repeat) {
  Mesh m;
  m.name = "disc";
  Vertex c;
  c.position = {0, y, 0};
  c.uv = {0.5f * uv_repeat, 0.5f * uv_repeat};
  m.vertices.push_back(c);
  for (int i = 0; i <= seg; ++i) {
    const float a = 2 * kPi * float(i) / float(seg);
    Vertex v;
    v.position = {r * std::sin(a), y, r * std::cos(a)};
    v.uv = {(0.5f + 0.5f * std::sin(a)) * uv_repeat, (0.5f + 0.5f * std::cos(a)) * uv_repeat};
    m.vertices.push_back(v);
  }
  for (int i = 0; i < seg; ++i) m.indices.insert(m.indices.end(), {0u, uint32_t(i + 1), uint32_t(i + 2)});
  return m;
}

Scene make_courtyard() {
  SceneBuilder b("courtyard",
                 "colonnade of pillars sharing one stone texture around a fountain and statue, "
                 "brick walls, banners, crates, benches and alpha-tested trees");
  const int t_cobbles = b.texture(cobbles(512, 101));
  const int t_light = b.texture(ground_lightmap(256));
  const int t_brick = b.texture(brick(512, 202));
  const int t_stone = b.texture(stone(512, 303));
  const int t_marble = b.texture(marble(512, 404));
  const int t_bronze = b.texture(metal(256, 505));
  const int t_water = b.texture(water(256, 606));
  const int t_wood = b.texture(wood(256, 707));
  const int t_bark = b.texture(bark(256, 808));
  const int t_leaves = b.texture(leaves(256, 909));
  const int t_sky = b.texture(sky(512, 1010));

  const int mat_ground = b.material(Material::textured("cobbles", t_cobbles, t_light, 2.0f));
  const auto simple = [&](const char* name, int tex) { return b.material(Material::textured(name, tex)); };
  const int mat_brick = simple("brick", t_brick);
  const int mat_stone = simple("stone", t_stone);
  const int mat_marble = simple("marble", t_marble);
  const int mat_bronze = simple("bronze", t_bronze);
  const int mat_water = simple("water", t_water);
  const int mat_wood = simple("wood", t_wood);
  const int mat_bark = simple("bark", t_bark);
  Material leaf = Material::textured("leaves", t_leaves);
  leaf.pass().alpha_func = AlphaFunc::gequal;
  leaf.pass().alpha_ref = 0.5f;
  leaf.two_sided = true;
  const int mat_leaves = b.material(leaf);

  // Floor and walls.
  b.object("ground", b.mesh(grid(2 * kHalf, 2 * kHalf, 40, 40, 12, 12)), mat_ground, Mat4::identity());
  const int wall_mesh = b.mesh(wall(2 * kHalf, 6, 20, 3, 10, 2));
  int walls[4];
  for (int i = 0; i < 4; ++i) {
    // Walls face inwards: rotate the +Z-facing wall about Y.
    const float a = kPi * 0.5f * float(i);
    const Mat4 t = rotate({0, 1, 0}, a) * translate({0, 0, -kHalf});
    walls[i] = b.object("wall-" + std::to_string(i), wall_mesh, mat_brick, t);
  }

  // Colonnade: every pillar is its own draw and samples the same stone texture.
  Mesh pillar = cylinder(kPillarRadius, 5.2f, 24, 6, 2, 4, false);
  append(pillar, box({0.75f, 0.2f, 0.75f}, 1), translate({0, 0.2f, 0}));
  append(pillar, box({0.8f, 0.3f, 0.8f}, 1), translate({0, 5.5f, 0}));
  const int pillar_mesh = b.mesh(pillar);
  for (int i = 0; i < kPillars; ++i) {
    const float a = 2 * kPi * float(i) / kPillars;
    b.object("pillar-" + std::to_string(i), pillar_mesh, mat_stone,
             translate({kColonnade * std::sin(a), 0, kColonnade * std::cos(a)}));
  }

  // Fountain: basin wall, rim, water, pedestal and a dense statue.
  const int basin = b.object("fountain-basin", b.mesh(cylinder(3.0f, 0.6f, 64, 2, 8, 1, false)), mat_marble, Mat4::identity());
  b.object("fountain-rim", b.mesh(torus(3.0f, 0.22f, 96, 16, 12, 1)), mat_marble, translate({0, 0.6f, 0}));
  // The water is what an engine would blend over the basin: it must follow it.
  const int water = b.object("fountain-water", b.mesh(disc(2.9f, 64, 0.45f, 3)), mat_water, Mat4::identity());
  b.scene().objects[size_t(water)].after.push_back(uint32_t(basin));
  b.object("statue-pedestal", b.mesh(cylinder(0.7f, 2.0f, 32, 4, 3, 2, true)), mat_marble, Mat4::identity());
  b.object("statue", b.mesh(sphere(1.0f, 96, 48, 4, 2)), mat_bronze, translate({0, 3.0f, 0}));

  // Crates and benches share the wood texture.
  Rng rng(4242);
  const int crate_mesh = b.mesh(box({0.5f, 0.5f, 0.5f}, 1));
  for (int i = 0; i < 12; ++i) {
    const float s = rng.uniform(0.6f, 1.4f);
    const float side = float(i % 4);
    const float along = rng.uniform(-15.0f, 15.0f);
    const Mat4 place = rotate({0, 1, 0}, kPi * 0.5f * side) * translate({along, 0.5f * s, -kHalf + 1.2f}) *
                       rotate({0, 1, 0}, rng.uniform(0.0f, 1.5f)) * scale({s, s, s});
    b.object("crate-" + std::to_string(i), crate_mesh, mat_wood, place);
  }
  Mesh bench = box({1.0f, 0.05f, 0.25f}, 2);
  bench.name = "bench";
  append(bench, box({0.05f, 0.2f, 0.22f}, 2), translate({-0.85f, -0.25f, 0}));
  append(bench, box({0.05f, 0.2f, 0.22f}, 2), translate({0.85f, -0.25f, 0}));
  const int bench_mesh = b.mesh(bench);
  for (int i = 0; i < 6; ++i) {
    const float a = 2 * kPi * (float(i) + 0.5f) / 6;
    b.object("bench-" + std::to_string(i), bench_mesh, mat_wood,
             translate({6.5f * std::sin(a), 0.45f, 6.5f * std::cos(a)}) * rotate({0, 1, 0}, a));
  }

  // Trees in the corners: bark trunks and alpha-tested, two-sided foliage.
  const int trunk_mesh = b.mesh(cylinder(0.3f, 4.0f, 12, 3, 2, 3, false));
  for (int i = 0; i < 4; ++i) {
    const float x = (i & 1) ? 16.5f : -16.5f, z = (i & 2) ? 16.5f : -16.5f;
    b.object("tree-trunk-" + std::to_string(i), trunk_mesh, mat_bark, translate({x, 0, z}));
    b.object("tree-crown-" + std::to_string(i), b.mesh(crossed_quads(5.0f, 5.0f, 6, 77 + uint64_t(i))), mat_leaves,
             translate({x, 2.5f, z}));
  }

  // Banners: each has its own texture (sharing level 1).
  const uint8_t colours[8][3] = {{180, 30, 30},  {30, 60, 160},  {30, 130, 50}, {150, 120, 20},
                                 {110, 40, 140}, {20, 120, 130}, {160, 80, 20}, {60, 60, 60}};
  const int banner_mesh = b.mesh(wall(2.0f, 3.0f, 1, 2, 1, 1));
  for (int i = 0; i < 8; ++i) {
    const int mat = b.material(Material::textured(
        "banner-" + std::to_string(i), b.texture(cloth(128, 1000 + uint64_t(i), colours[i][0], colours[i][1], colours[i][2]))));
    const float side = float(i % 4), along = (i < 4) ? -6.0f : 6.0f;
    const Mat4 t = rotate({0, 1, 0}, kPi * 0.5f * side) * translate({along, 2.0f, -kHalf + 0.03f});
    // Banners hang 3 cm in front of their wall, as decals: after the wall.
    const int banner = b.object("banner-" + std::to_string(i), banner_mesh, mat, t);
    b.scene().objects[size_t(banner)].after.push_back(uint32_t(walls[i % 4]));
  }

  // Sky dome last: with the early depth test only the pixels nothing else
  // covered are shaded, as engines draw skies.
  b.object("sky", b.mesh(dome(90.0f, 48, 12)), simple("sky", t_sky), Mat4::identity());

  // Camera: a walk around the fountain at eye height, looking inwards,
  // drifting in and out so that the view mixes near and far objects.
  CameraPath& cam = b.scene().camera;
  cam.fov_y_degrees = 90.0f;
  cam.z_near = 0.05f;
  cam.z_far = 200.0f;
  const int frames = 120;
  for (int f = 0; f < frames; ++f) {
    const float a = 2 * kPi * float(f) / float(frames) + 0.4f;
    const float r = 9.0f + 2.0f * std::sin(3 * a);
    CameraPose pose;
    pose.position = {r * std::sin(a), 1.7f, r * std::cos(a)};
    pose.target = {1.5f * std::sin(a + 1.2f), 1.4f, 1.5f * std::cos(a + 1.2f)};
    cam.frames.push_back(pose);
  }
  return b.take();
}

const BuiltinScenes::Add reg("courtyard", {"the default: pillars sharing one stone texture (paper Fig. 11), "
                                           "a dense statue, walls, banners, trees",
                                           make_courtyard});

}  // namespace
}  // namespace oovr
