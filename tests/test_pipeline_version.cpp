// The renderer's version (src/oovr/pipeline/version.h) against what the
// renderer writes: the traces of a few reference frames are held here by
// hash, beside the hash of their scene's content. A renderer change that
// changes a trace must bump kPipelineVersion, or a trace cache would replay
// the old output under the new code (the cache key holds the version, not
// the executable); this test fails until it does, naming the frame.
//
// The same frames' images (colour and object ids) are held by hash too: an
// optimisation of the renderer must leave every pixel as it was (issue 31's
// vector fragment stage); a change that moves a pixel is a model change, to
// be made with the reference comparison re-measured (docs/validation.md).
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "game_data.h"
#include "oovr/pipeline/pipeline.h"
#include "oovr/pipeline/trace_cache.h"
#include "oovr/pipeline/version.h"
#include "oovr/scene/load.h"
#include "oovr/scene/stereo.h"

namespace oovr {
namespace {

uint64_t fnv1a(std::string_view bytes, uint64_t h = 1469598103934665603ull) {
  for (const char c : bytes) h = (h ^ uint8_t(c)) * 1099511628211ull;
  return h;
}

struct Reference {
  const char* scene;
  int frame;
  const char* eye_resolution;
  uint64_t scene_hash;  // scene_fingerprint of the loaded scene
  uint64_t trace_hash;  // FNV-1a of serialize_trace of the rendered frame
  uint64_t image_hash;  // FNV-1a of the colour image's bytes, then the object ids'
  int max_anisotropy;   // 16 (the paper's, the default) or 1 (trilinear: the quad sampler)
  // Every pass given two fetch-only layers (a normal and a gloss map, as a
  // captured GLSL program's): what no loaded scene has.
  bool fetch_layers = false;
};

// Recorded with kPipelineVersion 2 (1 for all but the fetch layers' frame and
// the trilinear ones; the images' hashes at 178a519), and the same under 3,
// whose change none of these frames meets. When a frame's scene hash still matches
// and its trace hash does not, the renderer changed: bump kPipelineVersion and
// record the new trace hashes (with the version they belong to). When the
// scene hash changed too, a loader or a scene changed instead: record both.
constexpr uint32_t kRecordedVersion = 3;
constexpr Reference kReferences[] = {
    {"crowd", 0, "96x64", 7155168817299488758u, 16997077439721387403u, 1368127776875970968u, 16},
    {"courtyard", 5, "96x64", 6739315327548645814u, 11421391068056993798u, 7157077205418575661u, 16},
    {"oa:oa_dm4", 0, "96x64", 15964993765765942389u, 2787289683188192321u, 14305573863675941670u, 16},
    {"nexuiz:strength", 0, "96x64", 11821387306815008176u, 10426362947222672922u, 5579434252969499986u, 16},
    {"torcs:forza", 0, "96x64", 18442517620297510886u, 6131576962161297412u, 1799994838240830067u, 16},
    {"courtyard", 5, "96x64", 8638834991936059374u, 3747674295515319064u, 7157077205418575661u, 16, true},
    {"courtyard", 5, "96x64", 6739315327548645814u, 5869829498813623747u, 16803673726811024171u, 1},
    {"oa:oa_dm4", 0, "96x64", 15964993765765942389u, 15878291614353100390u, 10771577858151602583u, 1},
    {"nexuiz:strength", 0, "96x64", 11821387306815008176u, 12918620280778749103u, 11976852420045862991u, 1},
};

uint64_t image_fnv1a(const FrameOutput& out) {
  const std::string_view colour(reinterpret_cast<const char*>(out.colour.rgba.data()), out.colour.rgba.size());
  const std::string_view ids(reinterpret_cast<const char*>(out.object_id.data()), out.object_id.size() * sizeof(uint32_t));
  return fnv1a(ids, fnv1a(colour));
}

// A reference frame's scene, with every pass given the two fetch-only
// layers where asked.
Scene reference_scene(const std::string& name, bool fetch_layers) {
  Scene scene = load_scene(name);
  if (fetch_layers)
    for (Material& m : scene.materials)
      for (Pass& p : m.passes)
        if (p.shading == Shading::layers)
          for (LayerKind k : {LayerKind::normal, LayerKind::gloss})
            p.layers.push_back({k, 0, TexCoords::surface, Combine::fetch, 1.0f, {}});
  return scene;
}

bool installed(const std::string& scene) {
  if (scene.rfind("oa:", 0) == 0) return test::have_openarena();
  if (scene.rfind("nexuiz:", 0) == 0) return test::have_nexuiz();
  if (scene.rfind("torcs:", 0) == 0) return test::have_torcs();
  return true;
}

TEST(PipelineVersion, ReferenceTracesAreThoseOfThisVersion) {
  int checked = 0;
  for (const Reference& r : kReferences) {
    if (!installed(r.scene)) continue;
    const Scene scene = reference_scene(r.scene, r.fetch_layers);
    const StereoView view = make_stereo_view(scene.camera, r.frame, parse_eye_resolution(r.eye_resolution));
    PipelineSettings settings;
    settings.max_anisotropy = r.max_anisotropy;
    const FrameOutput out = render_frame(scene, view, settings, r.frame);
    const uint64_t scene_hash = scene_fingerprint(scene), trace_hash = fnv1a(serialize_trace(out.trace));
    const uint64_t image_hash = image_fnv1a(out);
    const std::string got =
        std::to_string(scene_hash) + "u, " + std::to_string(trace_hash) + "u, " + std::to_string(image_hash) + "u";
    const std::string what =
        std::string(r.scene) + " frame " + std::to_string(r.frame) + " (" + std::to_string(r.max_anisotropy) + "x anisotropic)";
    if (scene_hash != r.scene_hash) {
      ADD_FAILURE() << what << ": the scene's content changed (a loader or the scene); record " << got;
    } else if (trace_hash != r.trace_hash) {
      ADD_FAILURE() << what << ": the renderer's output changed; "
                    << (kPipelineVersion == kRecordedVersion
                            ? "bump kPipelineVersion in src/oovr/pipeline/version.h, then record "
                            : "record, with kRecordedVersion = kPipelineVersion, ")
                    << got;
    } else if (image_hash != r.image_hash) {
      ADD_FAILURE() << what << ": the image changed, the trace did not; a change to the pixels is a model change "
                    << "(re-measure the reference comparison), then record " << image_hash << "u";
    }
    ++checked;
  }
  EXPECT_EQ(kRecordedVersion, kPipelineVersion) << "the recorded traces are of another version: record them anew";
  if (checked < int(std::size(kReferences)))
    std::printf("[   NOTE   ] %d of %zu reference frames checked; the game levels' need scripts/install-deps.sh --game-data\n",
                checked, std::size(kReferences));
}

// Where two traces of a frame part: the first record or texture line that differs.
std::string difference(const FrameTrace& a, const FrameTrace& b) {
  if (a.tiles.size() != b.tiles.size())
    return std::to_string(a.tiles.size()) + " against " + std::to_string(b.tiles.size()) + " records";
  for (size_t i = 0; i < a.tiles.size(); ++i)
    if (!(a.tiles[i] == b.tiles[i])) return "record " + std::to_string(i) + " differs";
  if (a.tex_lines.size() != b.tex_lines.size())
    return std::to_string(a.tex_lines.size()) + " against " + std::to_string(b.tex_lines.size()) + " texture lines";
  for (size_t i = 0; i < a.tex_lines.size(); ++i)
    if (a.tex_lines[i] != b.tex_lines[i]) return "texture line " + std::to_string(i) + " differs";
  return "the records and lines are the same; the header or the objects differ";
}

// Drawn without the image (what `simulate`, `compare` and sweeps render for
// the frames whose picture they do not use), every reference frame gives the
// trace it gives with it, bit for bit, and no picture: the texture lines
// recorded without fetching a texel, alpha-tested passes shaded for their
// alpha, per-pixel lit and blended passes, 16x and trilinear, and a larger
// frame of each built-in scene with more of every kind of quad.
TEST(PipelineVersion, TheTraceDrawnWithoutTheImageIsTheSame) {
  struct Frame {
    const char* scene;
    int frame;
    const char* eye_resolution;
    int max_anisotropy;
    bool fetch_layers;
    bool record_texture_lines = true;
  };
  std::vector<Frame> frames;
  for (const Reference& r : kReferences) frames.push_back({r.scene, r.frame, r.eye_resolution, r.max_anisotropy, r.fetch_layers});
  for (const char* scene : {"crowd", "courtyard"})
    for (int aniso : {1, 16}) frames.push_back({scene, 3, "320x256", aniso, false});
  // Without texture lines (oovr-reference's timing): the lookups still counted alike.
  frames.push_back({"courtyard", 3, "320x256", 1, false, false});
  frames.push_back({"courtyard", 3, "320x256", 16, false, false});
  int checked = 0;
  for (const Frame& r : frames) {
    if (!installed(r.scene)) continue;
    const Scene scene = reference_scene(r.scene, r.fetch_layers);
    const StereoView view = make_stereo_view(scene.camera, r.frame, parse_eye_resolution(r.eye_resolution));
    PipelineSettings settings;
    settings.max_anisotropy = r.max_anisotropy;
    settings.record_texture_lines = r.record_texture_lines;
    const FrameOutput with = render_frame(scene, view, settings, r.frame);
    settings.draw_image = false;
    const FrameOutput without = render_frame(scene, view, settings, r.frame);
    const std::string what = std::string(r.scene) + " frame " + std::to_string(r.frame) + " at " + r.eye_resolution + " (" +
                             std::to_string(r.max_anisotropy) + "x anisotropic" +
                             (r.record_texture_lines ? "" : ", no texture lines") + ")";
    EXPECT_TRUE(serialize_trace(without.trace) == serialize_trace(with.trace))
        << what << ": " << difference(with.trace, without.trace);
    if (r.record_texture_lines) {
      EXPECT_GT(with.trace.tex_lines.size(), 0u) << what;
    } else {
      EXPECT_EQ(with.trace.tex_lines.size(), 0u) << what;
    }
    EXPECT_GT(with.trace.tiles.size(), 0u) << what;
    EXPECT_TRUE(without.colour.rgba.empty()) << what;
    EXPECT_TRUE(without.object_id.empty()) << what;
    ++checked;
  }
  EXPECT_GE(checked, 6);
}

}  // namespace
}  // namespace oovr
