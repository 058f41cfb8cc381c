// OO_Middleware (paper Section 5.1): groups objects that share textures into
// batches, the smallest units the multi-GPU system schedules.
//
// Take the object at the head of the queue as the root; for each next object
// that does not depend on one still waiting, compute the texture sharing
// level (Equation 1) between the root and it; above the threshold (0.5) the
// object joins, and the batch becomes the new root with the union of the
// textures. The batch closes once it holds more than the triangle cap (4096)
// or the queue has been searched to its end. An object that depends on a
// member joins at once, with the cap raised by its triangles, so that it
// follows the programmer's order on the same GPM.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "oovr/framework/oo_application.h"

namespace oovr {

// (texture, bytes) pairs; a texture appears once.
using TextureSet = std::vector<std::pair<uint32_t, uint64_t>>;

// Equation 1: TSL = sum over shared textures t of P_r(t) * P_n(t), divided by
// the sum over the same t of P_r(t), where P_x(t) is t's share of the bytes
// of all textures x requires. 0 when nothing is shared (or a set is empty).
double texture_sharing_level(const TextureSet& root, const TextureSet& next);

struct Batch {
  std::vector<uint32_t> objects;  // object ids, in the programmer's order
  uint64_t triangles = 0;
  uint64_t vertices = 0;
  TextureSet textures;  // the union of its objects' textures
};

struct MiddlewareSettings {
  double tsl_threshold = 0.5;    // Section 5.1
  uint64_t triangle_cap = 4096;  // Section 5.1
};

std::vector<Batch> make_batches(const OOApplication& app, const MiddlewareSettings& s);

}  // namespace oovr
