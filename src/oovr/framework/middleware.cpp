#include "oovr/framework/middleware.h"

#include <algorithm>
#include <functional>

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
  // The queue is the objects still waiting, in the programmer's order: a
  // flag per object and the index of the first, rather than a list that
  // each taken object is searched for in (quadratic in the draws: it was
  // 1.6% of the paper's sweep, batching every frame of every OO-VR point).
  const auto& objects = app.objects();
  const uint32_t n = uint32_t(objects.size());
  std::vector<uint8_t> waiting(n, 1), member(n, 0);
  uint32_t head = 0, left = n;
  std::vector<Batch> batches;

  while (left > 0) {
    while (!waiting[head]) ++head;
    Batch b;
    uint64_t cap = s.triangle_cap;
    const auto take = [&](uint32_t o) {
      member[o] = 1;
      waiting[o] = 0;
      --left;
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
      return std::any_of(objects[o].after.begin(), objects[o].after.end(), [&](uint32_t p) { return member[p] != 0; });
    };
    const auto independent = [&](uint32_t o) {
      return std::none_of(objects[o].after.begin(), objects[o].after.end(), [&](uint32_t p) { return waiting[p] != 0; });
    };

    // The search runs through the queue in order: what take() removes lies
    // at or before the object searched (an object's predecessors come
    // before it), so the objects after it are those still to search.
    take(head);
    for (uint32_t o = head + 1; o < n && b.triangles <= cap; ++o) {
      if (!waiting[o]) continue;
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
      for (uint32_t o = head; o < n; ++o)
        if (waiting[o] && depends_on_member(o)) {
          take_with_predecessors(o);
          again = true;
        }
    }
    for (uint32_t o : b.objects) member[o] = 0;
    std::sort(b.objects.begin(), b.objects.end());
    batches.push_back(std::move(b));
  }
  return batches;
}

}  // namespace oovr
