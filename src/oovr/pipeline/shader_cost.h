// What a pass costs a fragment lane, in scalar instructions.
//
// GPUs since NVIDIA's G80 run shaders on scalar lanes (SIMT): a vec4
// multiply is four instructions, an interpolated attribute one per
// component, a texture lookup one issued instruction whatever its filter
// (the texture unit does the filtering; the timing model charges it as
// samples). The counts below follow the SASS a GLSL fragment shader
// becomes on those GPUs (NVIDIA's CUDA Binary Utilities, "Instruction Set
// Reference": IPA interpolates one component, MUFU.RCP gives 1/w, FMUL and
// FFMA one component, TEX one lookup, KIL a discard); blending is done by
// the ROPs and costs no shader instruction. docs/model.md lists them.
#pragma once

#include <cstdint>

#include "oovr/scene/material.h"

namespace oovr {

struct FragmentCosts {
  static constexpr uint32_t setup = 2;        // IPA 1/w, MUFU.RCP
  static constexpr uint32_t output = 4;       // RGBA to the ROPs
  static constexpr uint32_t coordinates = 4;  // per layer: IPA u, v and two FMUL by w
  static constexpr uint32_t transform = 4;    // per transformed layer: two FFMA per coordinate
  static constexpr uint32_t lookup = 1;       // per layer: TEX
  static constexpr uint32_t scale = 3;        // a layer's RGB scale: FMUL per channel
  static constexpr uint32_t colour = 4;       // the pass colour, when not white: FMUL per channel
  static constexpr uint32_t combine = 4;      // modulate (FMUL) or add (FFMA x3, FMUL alpha) per layer after the first
  static constexpr uint32_t alpha_test = 2;   // FSETP, KIL

  // Shading::deluxe (DarkPlaces' per-pixel lighting), written out as
  // scalar operations of the formula in scene/material.h; a normalize is a
  // dot product (FMUL, 2 FFMA), MUFU.RSQ and three FMUL (7).
  static constexpr uint32_t lit_varyings = 24;     // IPA and FMUL by w for S, T, N and the eye vector (12 each)
  static constexpr uint32_t light_direction = 19;  // deluxe texel x2-1 (3 FFMA), into S/T/N (3 dot = 9), normalize (7)
  static constexpr uint32_t light_colour = 5;      // max(0.25, L.z), MUFU.RCP, 3 FMUL of the lightmap texel
  static constexpr uint32_t surface_normal = 10;   // normal texel - 0.5 (3 FADD), normalize (7); with a normal layer
  static constexpr uint32_t diffuse_light = 10;    // N.L (3), max (1), diffuse x N.L x light (6)
  static constexpr uint32_t specular = 31;         // normalize eye (7), L + E (3), normalize (7), N.H and max (4),
                                                   // pow: MUFU.LG2, 2 FMUL, MUFU.EX2 (4), gloss x spec x light (6)
  static constexpr uint32_t glow = 3;              // FADD per channel
};

// Scalar instructions one fragment lane runs for `pass`.
uint32_t fragment_instructions(const Pass& pass);

}  // namespace oovr
