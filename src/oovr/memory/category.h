// Traffic categories: what a byte moved was for, so that inter-GPM traffic
// can be broken down like the paper's Figures 9 and 16.
#pragma once

#include <cstdint>

namespace oovr {

enum class Category : uint8_t { vertex, index, texture, depth, colour, composition, prealloc, command };
constexpr int kCategories = 8;

constexpr const char* category_name(Category c) {
  constexpr const char* names[kCategories] = {"vertex", "index",       "texture",  "depth",
                                              "colour", "composition", "prealloc", "command"};
  return names[int(c)];
}

// Shader-side reads (vertex fetch, texture units) pass through the SM's L1;
// the ROPs' depth and colour traffic, composition and commands go to the L2.
constexpr bool uses_l1(Category c) { return c == Category::vertex || c == Category::index || c == Category::texture; }

}  // namespace oovr
