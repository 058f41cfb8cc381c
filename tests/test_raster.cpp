// Rasteriser invariants: shared edges are covered exactly once, no gaps,
// pixel-centre sampling and the fill rule on edges through pixel centres.
#include <gtest/gtest.h>

#include <cmath>

#include <cstring>
#include <limits>

#include "oovr/core/rng.h"
#include "oovr/pipeline/raster.h"
#include "test_util.h"

namespace oovr {
namespace {

using test::exact_settings;
using test::ortho_view;
using test::triangle_scene;

uint64_t written_pixels(const FrameOutput& out) {
  uint64_t n = 0;
  for (uint32_t id : out.object_id) n += id != kNoObject;
  return n;
}

// Covered fragments summed over the trace equal the number of distinct
// pixels written when no pixel is covered twice: with every triangle at the
// same depth, a second fragment on a pixel fails GL_LESS and is not written.
void expect_single_coverage(const Scene& s, const StereoView& v) {
  const FrameOutput out = render_frame(s, v, exact_settings());
  EXPECT_EQ(out.trace.total_covered(), written_pixels(out)) << "a pixel was covered twice";
  EXPECT_EQ(out.trace.total_passed(), written_pixels(out));
}

TEST(Raster, PixelCentreSamplingOfAnAxisAlignedRectangle) {
  // Rectangle from (2.3, 1.7) to (10.6, 5.2): pixel centres x+0.5 in
  // [2.3, 10.6] -> x = 2..10 (9 columns); y+0.5 in [1.7, 5.2] -> y = 2..4.
  const Scene s = triangle_scene({{2.3f, 1.7f}, {10.6f, 1.7f}, {10.6f, 5.2f}, {2.3f, 5.2f}}, {0, 1, 2, 0, 2, 3});
  const FrameOutput out = render_frame(s, ortho_view(16, 16), exact_settings());
  EXPECT_EQ(out.trace.total_covered(), 9u * 3u);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      const bool inside = x >= 2 && x <= 10 && y >= 2 && y <= 4;
      EXPECT_EQ(out.object_id[size_t(y) * 16 + x] == 0, inside) << x << "," << y;
    }
}

TEST(Raster, FillRuleOnEdgesThroughPixelCentres) {
  // A rectangle whose four edges pass exactly through pixel centres: the
  // rule (bottom-left in OpenGL window coordinates, llvmpipe's) keeps the
  // left column and the bottom row and drops the right column and top row.
  const Scene s = triangle_scene({{2.5f, 3.5f}, {8.5f, 3.5f}, {8.5f, 9.5f}, {2.5f, 9.5f}}, {0, 1, 2, 0, 2, 3});
  const FrameOutput out = render_frame(s, ortho_view(16, 16), exact_settings());
  EXPECT_EQ(out.trace.total_covered(), 6u * 6u);
  EXPECT_EQ(out.object_id[3 * 16 + 2], 0u) << "bottom-left corner pixel (on two included edges)";
  EXPECT_EQ(out.object_id[9 * 16 + 2], kNoObject) << "top row is excluded";
  EXPECT_EQ(out.object_id[3 * 16 + 8], kNoObject) << "right column is excluded";
}

TEST(Raster, SharedDiagonalCoveredOnce) {
  // The diagonal passes through pixel centres (x + 0.5 == y + 0.5).
  const Scene s = triangle_scene({{0, 0}, {16, 0}, {16, 16}, {0, 16}}, {0, 1, 2, 0, 2, 3});
  const FrameOutput out = render_frame(s, ortho_view(16, 16), exact_settings());
  EXPECT_EQ(out.trace.total_covered(), 256u);
  expect_single_coverage(s, ortho_view(16, 16));
}

TEST(Raster, SharedDiagonalOfALargeSquareCoveredOnce) {
  // The same at 2048x2048: near the diagonal a tile's edge values pass 2^30,
  // so it is drawn by the tile loop's 64-bit edges (edges_fit_32 fails),
  // where the 16x16 square's are 32-bit.
  const Scene s = triangle_scene({{0, 0}, {2048, 0}, {2048, 2048}, {0, 2048}}, {0, 1, 2, 0, 2, 3});
  const FrameOutput out = render_frame(s, ortho_view(2048, 2048), exact_settings());
  EXPECT_EQ(out.trace.total_covered(), 2048u * 2048u);
  EXPECT_EQ(written_pixels(out), 2048u * 2048u);
}

TEST(Raster, RandomFansHaveNoGapsAndNoOverlaps) {
  Rng rng(7);
  for (int trial = 0; trial < 40; ++trial) {
    // A convex polygon (points on an ellipse at random angles) triangulated
    // as a fan around a random interior point: many shared edges at
    // arbitrary sub-pixel positions.
    const float cx = rng.uniform(20, 44), cy = rng.uniform(20, 44);
    const float rx = rng.uniform(6, 19), ry = rng.uniform(6, 19);
    const int n = 3 + int(rng.below(14));
    std::vector<float> angles;
    for (int i = 0; i < n; ++i) angles.push_back(rng.uniform(0, 2 * kPi));
    std::sort(angles.begin(), angles.end());
    std::vector<Vec2> pts{{0, 0}};
    for (float a : angles) pts.push_back({cx + rx * std::cos(a), cy + ry * std::sin(a)});
    // Fan centre: the mean of the corners, inside the convex polygon.
    for (int i = 1; i <= n; ++i) pts[0] = {pts[0].x + pts[size_t(i)].x / float(n), pts[0].y + pts[size_t(i)].y / float(n)};
    std::vector<uint32_t> idx;
    for (int i = 0; i < n; ++i) idx.insert(idx.end(), {0u, uint32_t(1 + i), uint32_t(1 + (i + 1) % n)});
    const Scene s = triangle_scene(pts, idx);
    const FrameOutput out = render_frame(s, ortho_view(64, 64), exact_settings());
    EXPECT_EQ(out.trace.total_covered(), written_pixels(out)) << "trial " << trial << ": overlap";
    // No gaps: every pixel centre clearly inside the outer polygon is written.
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) {
        const float px = float(x) + 0.5f, py = float(y) + 0.5f;
        bool inside = true;
        for (int i = 0; i < n && inside; ++i) {
          const Vec2 a = pts[size_t(1 + i)], b = pts[size_t(1 + (i + 1) % n)];
          const float e = (b.x - a.x) * (py - a.y) - (b.y - a.y) * (px - a.x);
          const float len = std::hypot(b.x - a.x, b.y - a.y);
          inside = e / len > 0.01f;  // counter-clockwise polygon, margin 0.01 px
        }
        if (inside) {
          EXPECT_NE(out.object_id[size_t(y) * 64 + x], kNoObject) << "trial " << trial << ": gap at " << x << "," << y;
        }
      }
  }
}

TEST(Raster, BackFacesAreCulledUnlessTwoSided) {
  Scene s = triangle_scene({{1, 1}, {1, 12}, {12, 1}}, {0, 1, 2});  // clockwise on screen
  s.materials[0].two_sided = false;
  FrameOutput out = render_frame(s, ortho_view(16, 16), exact_settings());
  EXPECT_EQ(out.trace.total_covered(), 0u);
  EXPECT_EQ(out.trace.objects[0].culled[0], 1u);
  s.materials[0].two_sided = true;
  out = render_frame(s, ortho_view(16, 16), exact_settings());
  EXPECT_GT(out.trace.total_covered(), 0u);
}

TEST(Raster, NearPlaneClippingKeepsWhatIsInFront) {
  // A ground plane running from behind the camera to far ahead: without
  // near clipping its vertices behind the eye would project inverted.
  Scene s = triangle_scene({{-50, -1}, {50, -1}, {50, 100}, {-50, 100}}, {0, 1, 2, 0, 2, 3});
  for (auto& v : s.meshes[0].vertices) v.position = {v.position.x, -1.0f, -v.position.y};  // y = -1, z from 1 to -100
  s.camera.frames[0] = {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}};
  s.camera.z_near = 0.1f;
  s.camera.z_far = 1000.0f;
  StereoRig rig;
  rig.eye_width = 32;
  rig.eye_height = 32;
  const StereoView v = make_stereo_view(s.camera, 0, rig);
  const FrameOutput out = render_frame(s, v, exact_settings());
  EXPECT_GT(out.trace.objects[0].clipped[0], 0u);
  // The floor fills exactly the bottom half of each eye (below the horizon).
  for (int e = 0; e < 2; ++e)
    for (int y = 0; y < 32; ++y) {
      const uint32_t id = out.object_id[size_t(y) * 64 + size_t(e * 32 + 16)];
      if (y < 15) {
        EXPECT_EQ(id, 0u) << "eye " << e << " row " << y;
      } else if (y > 16) {
        EXPECT_EQ(id, kNoObject) << "eye " << e << " row " << y;
      }
    }
}

TEST(Raster, UnprojectableInputIsDroppedNotRasterised) {
  // A vertex exactly at the eye (w = 0 after clipping) and a transform
  // holding NaN: nothing to draw, and no overflow in the edge arithmetic
  // (UBSan checks that in `make asan`).
  Scene s = triangle_scene({{0, 0}, {1, 0}, {0, 1}}, {0, 1, 2});
  for (auto& v : s.meshes[0].vertices) v.position = {v.position.x, v.position.y, -v.position.x};
  s.meshes[0].vertices[0].position = {0, 0, 0};
  s.camera.frames[0] = {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}};
  StereoRig rig;
  rig.eye_width = 16;
  rig.eye_height = 16;
  const StereoView v = make_stereo_view(s.camera, 0, rig);
  EXPECT_NO_THROW(render_frame(s, v, exact_settings()));
  s.objects[0].world_from_object.at(0, 0) = std::nanf("");
  const FrameOutput out = render_frame(s, v, exact_settings());
  EXPECT_EQ(out.trace.total_covered(), 0u);
}

// The quad's depths by the FMA instruction (four lanes) are std::fma's,
// bit for bit, including planes whose products need the single rounding,
// out-of-range depths that clamp, and NaN planes.
TEST(Raster, QuadDepthsByTheFmaInstructionAreThoseOfStdFma) {
  if (!detail::cpu_has_fma()) GTEST_SKIP() << "this CPU has no FMA instructions: only the std::fma path runs";
  Rng rng(11);
  const auto bits = [](float f) {
    uint32_t u;
    std::memcpy(&u, &f, 4);
    return u;
  };
  int compared = 0;
  for (int n = 0; n < 200000; ++n) {
    detail::SetupTri t{};
    const float scale = n % 3 == 0 ? 1e-3f : (n % 3 == 1 ? 1.0f : 1e3f);
    t.dzdx = rng.uniform(-1, 1) * scale / 4096.0f;
    t.dzdy = rng.uniform(-1, 1) * scale / 4096.0f;
    t.z0 = rng.uniform(-0.5f, 1.5f);
    if (n % 1000 == 0) t.z0 = std::numeric_limits<float>::quiet_NaN();
    const int qx = int(rng.below(8192)) & ~1, qy = int(rng.below(8192)) & ~1;
    const detail::Float4 hw = detail::plane_depth(t, qx, qy, true), sw = detail::plane_depth(t, qx, qy, false);
    for (int p = 0; p < 4; ++p) {
      ASSERT_EQ(bits(hw[p]), bits(sw[p])) << "plane " << n << " pixel " << p;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 800000);
}

TEST(Raster, EveryPixelOfATileCutByTheFramesEdgeIsClearedOrDrawn) {
  // Tiles are drawn in buffers of their own and copied into the frame: a
  // frame of 37x21 pixels ends in tiles cut at its right and top edges,
  // whose pixels must be cleared (opaque black, no object) or drawn like
  // any other. The rectangle's edges lie between pixel centres: it covers
  // x = 3..34, y = 2..18, reaching into the cut tiles.
  const Scene s = triangle_scene({{3, 2}, {35, 2}, {35, 19}, {3, 19}}, {0, 1, 2, 0, 2, 3});
  for (unsigned threads : {1u, 2u}) {
    const FrameOutput out = render_frame(s, ortho_view(37, 21), exact_settings(threads));
    ASSERT_EQ(out.colour.width, 37);
    ASSERT_EQ(out.colour.height, 21);
    ASSERT_EQ(out.object_id.size(), 37u * 21u);
    EXPECT_EQ(out.trace.total_covered(), 32u * 17u);
    const uint8_t* drawn = out.colour.pixel(3, 2);
    EXPECT_NE(std::memcmp(drawn, "\0\0\0\xff", 4), 0) << "the rectangle is drawn in a colour other than the clear colour";
    for (int y = 0; y < 21; ++y)
      for (int x = 0; x < 37; ++x) {
        const bool inside = x >= 3 && x <= 34 && y >= 2 && y <= 18;
        const uint8_t* c = out.colour.pixel(x, y);
        EXPECT_EQ(out.object_id[size_t(y) * 37 + size_t(x)], inside ? 0u : kNoObject) << x << "," << y;
        if (inside) EXPECT_EQ(std::memcmp(c, drawn, 4), 0) << x << "," << y;
        else EXPECT_TRUE(c[0] == 0 && c[1] == 0 && c[2] == 0 && c[3] == 255) << "not cleared: " << x << "," << y;
      }
  }
}

}  // namespace
}  // namespace oovr
