// oovr check-capture: a captured game's frames against glretrace's
// snapshots of them, or a capture of a built-in scene against the scene
// (the round trip); docs/validation.md.
#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "commands.h"
#include "oovr/core/error.h"
#include "oovr/core/text.h"
#include "oovr/experiments/capture_check.h"
#include "oovr/scene/load.h"

namespace oovr::cli {

namespace {

std::string decibels(double psnr) { return std::isinf(psnr) ? std::string("identical") : fmt::format("{:.2f}", psnr); }

int against_snapshots(const CheckCaptureArgs& a) {
  CaptureCheckOptions o;
  o.snapshots = a.snapshots;
  o.diff_dir = a.images;
  const Scene scene = load_scene(a.scene);
  const std::vector<CaptureFrameCheck> frames = check_capture(scene, o);
  fmt::print("{}: {} frames at {}x{}, mono, against glretrace's snapshots in {}\n", printable(scene.name), frames.size(),
             scene.capture_width, scene.capture_height, printable(a.snapshots));
  fmt::print("  {:>10} {:>6} {:>9} {:>6} {:>9}\n", "game frame", "draws", "triangles", "clears", "PSNR dB");
  int good = 0, compared = 0;
  std::vector<double> all;
  for (const auto& f : frames) {
    if (f.snapshot) {
      ++compared;
      good += f.psnr >= a.min_psnr;
      all.push_back(f.psnr);
    }
    fmt::print("  {:>10} {:>6} {:>9} {:>6} {:>9}\n", f.game_frame, f.draws, f.triangles, f.clears,
               f.snapshot ? decibels(f.psnr) : std::string("no snapshot"));
  }
  std::sort(all.begin(), all.end());
  fmt::print("{} of {} frames compared reach {:.1f} dB (median {}, lowest {}); {} needed\n", good, compared, a.min_psnr,
             all.empty() ? "-" : decibels(all[all.size() / 2]), all.empty() ? "-" : decibels(all.front()), a.min_frames);
  if (good < a.min_frames)
    throw Error(fmt::format("{} of {} frames reach {:.1f} dB against glretrace's snapshots; {} must", good, compared, a.min_psnr,
                            a.min_frames));
  return 0;
}

double percent(uint64_t a, uint64_t b) { return b ? std::abs(double(a) - double(b)) / double(b) * 100.0 : (a ? 100.0 : 0.0); }

int against_scene(const CheckCaptureArgs& a) {
  const Scene captured = load_scene(a.scene);
  const Scene original = load_scene(a.against);
  const std::vector<RoundTripFrame> frames = check_round_trip(captured, original);
  fmt::print("{}: {} frames at {}x{}, mono, against {} drawn by oovr\n", printable(captured.name), frames.size(),
             captured.capture_width, captured.capture_height, printable(original.name));
  fmt::print("  {:>5} {:>11} {:>15} {:>21} {:>21} {:>21} {:>9}\n", "frame", "draws", "triangles", "covered fragments",
             "passed fragments", "texture fetches", "PSNR dB");
  const auto pair = [](const uint64_t v[2]) { return fmt::format("{} {}", v[0], v[1]); };
  std::vector<std::string> failures;
  for (const auto& f : frames) {
    fmt::print("  {:>5} {:>11} {:>15} {:>21} {:>21} {:>21} {:>9}\n", f.frame, pair(f.draws), pair(f.triangles), pair(f.covered),
               pair(f.passed), pair(f.fetches), decibels(f.psnr));
    const double worst = std::max({percent(f.covered[0], f.covered[1]), percent(f.passed[0], f.passed[1])});
    if (f.draws[0] != f.draws[1] || f.triangles[0] != f.triangles[1])
      failures.push_back(fmt::format("frame {} has other draws or triangles", f.frame));
    else if (f.psnr < a.min_psnr)
      failures.push_back(fmt::format("frame {} reaches {:.2f} dB, under {:.1f}", f.frame, f.psnr, a.min_psnr));
    else if (worst > a.max_fragment_diff)
      failures.push_back(fmt::format("frame {}'s fragments differ by {:.4f}%, over {}%", f.frame, worst, a.max_fragment_diff));
  }
  fmt::print("(each column: the capture, then the scene)\n");
  if (!failures.empty())
    throw Error(fmt::format("the capture differs from {}: {}{}", printable(original.name), failures.front(),
                            failures.size() > 1 ? fmt::format(" (and {} more frames)", failures.size() - 1) : ""));
  fmt::print("every frame has the same draws and triangles, reaches {:.1f} dB and its fragments are within {}%\n", a.min_psnr,
             a.max_fragment_diff);
  return 0;
}

}  // namespace

int check_capture(const CheckCaptureArgs& a) {
  if (a.snapshots.empty() == a.against.empty())
    throw Error("check-capture: give --snapshots (glretrace's images) or --against (the scene that was captured)");
  if (!a.against.empty() && !a.images.empty()) throw Error("check-capture: --images goes with --snapshots");
  return a.snapshots.empty() ? against_scene(a) : against_snapshots(a);
}

}  // namespace oovr::cli
