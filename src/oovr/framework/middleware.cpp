#include "oovr/framework/middleware.h"

#include <algorithm>
#include <functional>
#include <list>

namespace oovr {
namespace {

uint64_t total_bytes(const TextureSet& s) {
  uint64_t b = 0;
  for (const auto& [t, bytes] : s) b += bytes;
  return b;
}

void add_textures(TextureSet& into, const TextureSet& from) {
  for (const auto& x : from)
    if (std::none_of(into.begin(), into.end(), [&](const auto& y) { return y.first == x.first; })) into.push_back(x);
}

}  // namespace

double texture_sharing_level(const TextureSet& root, const TextureSet& next) {
  const double root_total = double(total_bytes(root)), next_total = double(total_bytes(next));
  if (root_total <= 0 || next_total <= 0) return 0;
  double num = 0, den = 0;
  for (const auto& entry : root) {
    const uint32_t t = entry.first;  // (Clang 14 cannot capture structured bindings.)
    const auto it = std::find_if(next.begin(), next.end(), [&](const auto& y) { return y.first == t; });
    if (it == next.end()) continue;
    const double pr = double(entry.second) / root_total, pn = double(it->second) / next_total;
    num += pr * pn;
    den += pr;
  }
  return den > 0 ? num / den : 0;
}

std::vector<Batch> make_batches(const OOApplication& app, const MiddlewareSettings& s) {
  const auto& objects = app.objects();
  std::vector<bool> waiting(objects.size(), true);
  std::list<uint32_t> queue;
  for (uint32_t i = 0; i < objects.size(); ++i) queue.push_back(i);
  std::vector<Batch> batches;

  while (!queue.empty()) {
    Batch b;
    std::vector<bool> member(objects.size(), false);
    uint64_t cap = s.triangle_cap;
    const auto take = [&](uint32_t o) {
      member[o] = true;
      waiting[o] = false;
      queue.remove(o);
      b.objects.push_back(o);
      b.triangles += objects[o].triangles;
      b.vertices += objects[o].vertices;
      add_textures(b.textures, objects[o].textures);
    };
    // Takes `o` with every predecessor still waiting (earlier ones first),
    // raising the cap by their triangles: a dependent object and what it
    // follows stay together, in order.
    const std::function<void(uint32_t)> take_with_predecessors = [&](uint32_t o) {
      for (uint32_t p : objects[o].after)
        if (waiting[p]) take_with_predecessors(p);
      if (!waiting[o]) return;
      cap += objects[o].triangles;
      take(o);
    };
    const auto depends_on_member = [&](uint32_t o) {
      return std::any_of(objects[o].after.begin(), objects[o].after.end(), [&](uint32_t p) { return member[p]; });
    };
    const auto independent = [&](uint32_t o) {
      return std::none_of(objects[o].after.begin(), objects[o].after.end(), [&](uint32_t p) { return waiting[p]; });
    };

    take(queue.front());
    for (auto it = queue.begin(); it != queue.end() && b.triangles <= cap;) {
      const uint32_t o = *it++;
      if (!waiting[o]) continue;
      // `it` is past o, and whatever take() removes comes before it (an
      // object's predecessors are earlier in the queue): it stays valid.
      if (depends_on_member(o)) {
        take_with_predecessors(o);
        continue;
      }
      if (!independent(o)) continue;
      if (texture_sharing_level(b.textures, objects[o].textures) > s.tsl_threshold) take(o);
    }
    // Whatever follows a member joins too, however large the batch is.
    for (bool again = true; again;) {
      again = false;
      for (uint32_t o : std::vector<uint32_t>(queue.begin(), queue.end()))
        if (waiting[o] && depends_on_member(o)) {
          take_with_predecessors(o);
          again = true;
        }
    }
    std::sort(b.objects.begin(), b.objects.end());
    batches.push_back(std::move(b));
  }
  return batches;
}

}  // namespace oovr
