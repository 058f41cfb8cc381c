// sfr-lb (not in the OO-VR paper): tile-level SFR whose strips follow the
// load, as Equalizer's load equalizer balances a sort-first compound
// (Eilemann, Makhinya and Pajarola, "Equalizer: A Scalable Parallel
// Rendering Framework", IEEE TVCG 2009): each frame's split comes from the
// time each part took in the frame before.
//
// The frame is cut into one vertical strip of whole tile columns per GPM,
// as sfr-v cuts it, and rendered as sfr-v renders it (every draw to every
// GPM, its geometry on every GPM whose strip it reaches, once per eye
// covered). After each frame, each strip's busy time spread evenly over its
// columns gives a cost per column; the boundaries that would cut that cost
// into equal parts are the target, and the next frame's boundaries move
// `1 - sfr_lb.damping` of the way there (Equalizer's load equalizer damps
// its split the same way). A column belongs to the strip its centre lies
// in; every strip keeps at least one column. The first frame of a sequence
// is split evenly (sfr-v's split).
//
// Assumed where the source is silent: vertical strips (Equalizer also
// splits in 2-D); each GPM's busy time as the time of its part (Equalizer
// measures each channel's draw time); the damping's default, 0.5.
#include <algorithm>
#include <cmath>
#include <string>

#include "oovr/core/config_sections.h"
#include "oovr/schemes/sort_first.h"

namespace oovr {
namespace {

struct LbSettings {
  double damping = 0.5;
  static LbSettings from_config(const Config& c) { return {c.get_double("sfr_lb.damping", 0.5, 0, 1)}; }
};

constexpr const char* kBoundsKey = "sfr-lb.bounds";

// Strip boundaries in tile columns: b[0] = 0 <= b[1] <= ... <= b[n] = tiles_x.
std::vector<double> even_split(int n, int tiles_x) {
  std::vector<double> b(size_t(n) + 1);
  for (int k = 0; k <= n; ++k) b[size_t(k)] = double(tiles_x) * k / n;
  return b;
}

bool usable(const std::vector<double>& b, int n, int tiles_x) {
  if (b.size() != size_t(n) + 1 || b.front() != 0 || b.back() != double(tiles_x)) return false;
  for (size_t k = 1; k < b.size(); ++k)
    if (!(b[k] >= b[k - 1])) return false;
  return true;
}

// The strip whose span holds column `tx`'s centre.
int strip_of(const std::vector<double>& b, int tx) {
  const double centre = tx + 0.5;
  const auto it = std::upper_bound(b.begin() + 1, b.end() - 1, centre);
  return int(it - (b.begin() + 1));
}

// The next frame's boundaries from this frame's and each strip's time.
std::vector<double> rebalance(const std::vector<double>& b, const std::vector<double>& time, double damping) {
  const size_t n = time.size();
  double total = 0;
  for (double t : time) total += t;
  if (!(total > 0)) return b;
  std::vector<double> target = b;
  double before = 0;  // cost left of strip k
  size_t k = 0;
  for (size_t j = 1; j < n; ++j) {
    const double want = total * double(j) / double(n);
    while (k + 1 < n && before + time[k] < want) before += time[k++];
    const double width = b[k + 1] - b[k];
    target[j] = time[k] > 0 ? b[k] + std::min(1.0, (want - before) / time[k]) * width : b[k + 1];
  }
  std::vector<double> next(b.size());
  next.front() = b.front();
  next.back() = b.back();
  for (size_t j = 1; j < n; ++j) next[j] = damping * b[j] + (1 - damping) * target[j];
  // At least one column each (or an even share where there are fewer
  // columns than strips).
  const double least = std::min(1.0, b.back() / double(n));
  for (size_t j = 1; j < n; ++j) next[j] = std::max(next[j], next[j - 1] + least);
  for (size_t j = n - 1; j >= 1; --j) next[j] = std::min(next[j], next[j + 1] - least);
  return next;
}

class SfrLb final : public Scheme {
 public:
  SchemeResult run(const SchemeInput& in) const override {
    FrameSim sim(in);
    const int n = sim.gpms(), tiles_x = sim.frame().tiles_x;
    CarriedState* carried = in.carried.get();
    std::vector<double> bounds = even_split(n, tiles_x);
    if (carried) {
      const auto it = carried->values.find(kBoundsKey);
      if (it != carried->values.end() && usable(it->second, n, tiles_x)) bounds = it->second;
    }
    sort_first(
        sim, [&](int tx, int, int) { return strip_of(bounds, tx); }, Geometry::duplicated_per_eye);
    SchemeResult r = sim.finish("sfr-lb");
    if (carried) carried->values[kBoundsKey] = rebalance(bounds, r.gpm_busy_s, in.spec->own<LbSettings>("sfr_lb").damping);
    // Where the strips were this frame (their boundaries, in tile columns).
    for (int k = 1; k < n; ++k) r.add_own("bound." + std::to_string(k), bounds[size_t(k)], "columns");
    return r;
  }
};

const ConfigSections::Add settings("sfr_lb",
                                   {"sfr-lb's settings (Equalizer's load equalizer)",
                                    nullptr,
                                    {{"sfr_lb.damping",
                                      "share of the way to the balanced split the strips do not move each frame (0: all of it; "
                                      "assumed 0.5)"}},
                                    true,
                                    [](const Config& c) { return std::any(LbSettings::from_config(c)); }});

const Schemes::Add reg("sfr-lb", {"tile SFR, vertical strips moved each frame to balance the last frame's times (Equalizer)",
                                  [] { return std::make_unique<SfrLb>(); },
                                  65,
                                  {"sfr_lb"}});

}  // namespace
}  // namespace oovr
