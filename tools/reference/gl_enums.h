// oovr's fragment state as OpenGL enumerants, for both of the reference's
// renderers (gl_renderer.cpp, fixed_function.cpp). Include after the
// OpenGL header the file draws with (they define the same values).
#pragma once

#include "oovr/scene/material.h"

namespace oovr::reference {

inline GLenum gl_blend(BlendFactor f) {
  switch (f) {
    case BlendFactor::zero: return GL_ZERO;
    case BlendFactor::one: return GL_ONE;
    case BlendFactor::src_colour: return GL_SRC_COLOR;
    case BlendFactor::one_minus_src_colour: return GL_ONE_MINUS_SRC_COLOR;
    case BlendFactor::src_alpha: return GL_SRC_ALPHA;
    case BlendFactor::one_minus_src_alpha: return GL_ONE_MINUS_SRC_ALPHA;
    case BlendFactor::dst_colour: return GL_DST_COLOR;
    case BlendFactor::one_minus_dst_colour: return GL_ONE_MINUS_DST_COLOR;
    case BlendFactor::dst_alpha: return GL_DST_ALPHA;
    case BlendFactor::one_minus_dst_alpha: return GL_ONE_MINUS_DST_ALPHA;
  }
  return GL_ONE;
}

inline GLenum gl_depth(DepthFunc f) {
  switch (f) {
    case DepthFunc::less: return GL_LESS;
    case DepthFunc::lequal: return GL_LEQUAL;
    case DepthFunc::equal: return GL_EQUAL;
    case DepthFunc::always: return GL_ALWAYS;
  }
  return GL_LESS;
}

inline GLenum gl_alpha(AlphaFunc f) {
  switch (f) {
    case AlphaFunc::always: return GL_ALWAYS;
    case AlphaFunc::greater: return GL_GREATER;
    case AlphaFunc::less: return GL_LESS;
    case AlphaFunc::gequal: return GL_GEQUAL;
  }
  return GL_ALWAYS;
}

}  // namespace oovr::reference
