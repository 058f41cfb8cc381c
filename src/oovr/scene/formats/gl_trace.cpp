#include "oovr/scene/formats/gl_trace.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <unordered_map>

#include "oovr/core/error.h"
#include "oovr/core/limits.h"
#include "oovr/scene/formats/apitrace.h"
#include "oovr/scene/formats/gl_programs.h"

namespace oovr {

namespace {

using apitrace::Call;
using apitrace::Value;

// OpenGL 1.x enumerants (the GL 1.5 and ARB_multitexture headers).
enum : int64_t {
  GL_POINTS = 0,
  GL_LINES,
  GL_LINE_LOOP,
  GL_LINE_STRIP,
  GL_TRIANGLES,
  GL_TRIANGLE_STRIP,
  GL_TRIANGLE_FAN,
  GL_QUADS,
  GL_QUAD_STRIP,
  GL_POLYGON,
  GL_BYTE = 0x1400,
  GL_UNSIGNED_BYTE,
  GL_SHORT,
  GL_UNSIGNED_SHORT,
  GL_INT,
  GL_UNSIGNED_INT,
  GL_FLOAT,
  GL_DOUBLE = 0x140A,
  GL_MODELVIEW = 0x1700,
  GL_PROJECTION,
  GL_TEXTURE,
  GL_TEXTURE_2D = 0x0DE1,
  GL_BLEND = 0x0BE2,
  GL_ALPHA_TEST = 0x0BC0,
  GL_DEPTH_TEST = 0x0B71,
  GL_CULL_FACE = 0x0B44,
  GL_POLYGON_OFFSET_FILL = 0x8037,
  GL_SCISSOR_TEST = 0x0C11,
  GL_FOG = 0x0B60,
  GL_LIGHTING = 0x0B50,
  GL_STENCIL_TEST = 0x0B90,
  GL_CLIP_PLANE0 = 0x3000,
  GL_TEXTURE_GEN_S = 0x0C60,
  GL_TEXTURE_GEN_Q = 0x0C63,
  GL_DITHER = 0x0BD0,
  GL_MULTISAMPLE = 0x809D,
  GL_NORMALIZE = 0x0BA1,
  GL_COLOR_MATERIAL = 0x0B57,
  GL_RESCALE_NORMAL = 0x803A,
  GL_LINE_SMOOTH = 0x0B20,
  GL_POINT_SMOOTH = 0x0B10,
  GL_LINE_STIPPLE = 0x0B24,
  GL_LIGHT0 = 0x4000,
  GL_LIGHT7 = 0x4007,
  GL_VERTEX_ARRAY = 0x8074,
  GL_NORMAL_ARRAY,
  GL_COLOR_ARRAY,
  GL_INDEX_ARRAY,
  GL_TEXTURE_COORD_ARRAY,
  GL_EDGE_FLAG_ARRAY,
  GL_TEXTURE0 = 0x84C0,
  GL_ZERO = 0,
  GL_ONE = 1,
  GL_SRC_COLOR = 0x300,
  GL_ONE_MINUS_SRC_COLOR,
  GL_SRC_ALPHA,
  GL_ONE_MINUS_SRC_ALPHA,
  GL_DST_ALPHA,
  GL_ONE_MINUS_DST_ALPHA,
  GL_DST_COLOR,
  GL_ONE_MINUS_DST_COLOR,
  GL_NEVER = 0x200,
  GL_LESS,
  GL_EQUAL,
  GL_LEQUAL,
  GL_GREATER,
  GL_NOTEQUAL,
  GL_GEQUAL,
  GL_ALWAYS,
  GL_FRONT = 0x404,
  GL_BACK = 0x405,
  GL_FRONT_AND_BACK = 0x408,
  GL_CW = 0x900,
  GL_CCW = 0x901,
  GL_BACK_LEFT = 0x402,
  GL_TEXTURE_MAG_FILTER = 0x2800,
  GL_TEXTURE_MIN_FILTER,
  GL_TEXTURE_WRAP_S,
  GL_TEXTURE_WRAP_T,
  GL_NEAREST = 0x2600,
  GL_LINEAR,
  GL_NEAREST_MIPMAP_NEAREST = 0x2700,
  GL_LINEAR_MIPMAP_NEAREST,
  GL_NEAREST_MIPMAP_LINEAR,
  GL_LINEAR_MIPMAP_LINEAR,
  GL_CLAMP = 0x2900,
  GL_REPEAT = 0x2901,
  GL_CLAMP_TO_EDGE = 0x812F,
  GL_RED = 0x1903,
  GL_ALPHA = 0x1906,
  GL_RGB,
  GL_RGBA,
  GL_LUMINANCE,
  GL_LUMINANCE_ALPHA,
  GL_BGR = 0x80E0,
  GL_BGRA,
  GL_TEXTURE_ENV = 0x2300,
  GL_TEXTURE_ENV_MODE = 0x2200,
  GL_MODULATE = 0x2100,
  GL_DECAL = 0x2101,
  GL_REPLACE = 0x1E01,
  GL_ADD = 0x0104,
  // GL_ARB_texture_env_combine (core in OpenGL 1.3).
  GL_COMBINE = 0x8570,
  GL_COMBINE_RGB = 0x8571,
  GL_COMBINE_ALPHA = 0x8572,
  GL_RGB_SCALE = 0x8573,
  GL_CONSTANT = 0x8576,
  GL_PRIMARY_COLOR = 0x8577,
  GL_PREVIOUS = 0x8578,
  GL_SRC0_RGB = 0x8580,
  GL_SRC0_ALPHA = 0x8588,
  GL_OPERAND0_RGB = 0x8590,
  GL_OPERAND0_ALPHA = 0x8598,
  GL_ALPHA_SCALE = 0x0D1C,
  GL_UNPACK_ROW_LENGTH = 0x0CF2,
  GL_UNPACK_SKIP_ROWS,
  GL_UNPACK_SKIP_PIXELS,
  GL_UNPACK_ALIGNMENT,
  GL_COLOR_BUFFER_BIT = 0x4000,
  GL_DEPTH_BUFFER_BIT = 0x100,
  GL_STENCIL_BUFFER_BIT = 0x400,
  GL_FILL = 0x1B02,
  GL_FLAT = 0x1D00,
  GL_SMOOTH = 0x1D01,
  GL_ARRAY_BUFFER = 0x8892,
  GL_ELEMENT_ARRAY_BUFFER = 0x8893,
  GL_TEXTURE_CUBE_MAP_POSITIVE_X = 0x8515,
  GL_DEPTH_COMPONENT = 0x1902,
  GL_DEPTH_STENCIL = 0x84F9,
  // OpenGL 3: framebuffer objects, shaders.
  GL_FRAMEBUFFER = 0x8D40,
  GL_DRAW_FRAMEBUFFER = 0x8CA9,
  GL_READ_FRAMEBUFFER = 0x8CA8,
  GL_COLOR_ATTACHMENT0 = 0x8CE0,
  GL_FRAGMENT_SHADER = 0x8B30,
  GL_VERTEX_SHADER = 0x8B31,
};

constexpr int kUnits = 2;  // texture units oovr models (ioquake3's opengl1 uses two)
const Mat4 kIdentity = Mat4::identity();

// Calls that change nothing oovr draws: queries, context and window-system
// calls, hints, object names, performance hints, the unused normal, and
// state of features that an enabled-check refuses at draw time
// (fog, lighting, stencil, clip planes, texture generation: see
// refuse_state).
const std::set<std::string>& harmless_calls() {
  static const std::set<std::string> names = {"glGetError",
                                              "glGetString",
                                              "glGetStringi",
                                              "glGetIntegerv",
                                              "glGetFloatv",
                                              "glGetBooleanv",
                                              "glGetDoublev",
                                              "glGetTexParameteriv",
                                              "glGetTexParameterfv",
                                              "glGetTexLevelParameteriv",
                                              "glGetPointerv",
                                              "glIsEnabled",
                                              "glIsTexture",
                                              "glGetFramebufferAttachmentParameteriv",
                                              "glFinish",
                                              "glFlush",
                                              "glHint",
                                              "glGenTextures",
                                              "glDeleteTextures",
                                              "glClearColor",
                                              "glClearDepth",
                                              "glClearStencil",
                                              "glLineWidth",
                                              "glPointSize",
                                              "glNormal3f",
                                              "glNormal3fv",
                                              "glNormalPointer",
                                              "glFogf",
                                              "glFogfv",
                                              "glFogi",
                                              "glFogiv",
                                              "glLightf",
                                              "glLightfv",
                                              "glLightModelf",
                                              "glLightModelfv",
                                              "glMaterialf",
                                              "glMaterialfv",
                                              "glColorMaterial",
                                              "glTexGeni",
                                              "glTexGenf",
                                              "glTexGenfv",
                                              "glStencilFunc",
                                              "glStencilOp",
                                              "glStencilMask",
                                              "glClipPlane",
                                              "glLineStipple",
                                              "glReadPixels",
                                              "glReadBuffer",
                                              "glPixelStoref",
                                              "glLockArraysEXT",
                                              "glUnlockArraysEXT",
                                              "glXMakeCurrent",
                                              "glXMakeContextCurrent",
                                              "glXCreateContext",
                                              "glXCreateNewContext",
                                              "glXCreateContextAttribsARB",
                                              "glXDestroyContext",
                                              "glXGetProcAddressARB",
                                              "glXGetProcAddress",
                                              "glXChooseVisual",
                                              "glXChooseFBConfig",
                                              "glXGetFBConfigs",
                                              "glXGetFBConfigAttrib",
                                              "glXGetVisualFromFBConfig",
                                              "glXQueryExtension",
                                              "glXQueryExtensionsString",
                                              "glXQueryVersion",
                                              "glXGetConfig",
                                              "glXGetClientString",
                                              "glXQueryServerString",
                                              "glXIsDirect",
                                              "glXGetCurrentContext",
                                              "glXGetCurrentDisplay",
                                              "glXGetCurrentDrawable",
                                              "glXSwapIntervalEXT",
                                              "glXSwapIntervalMESA",
                                              "glXSwapIntervalSGI",
                                              "glXQueryDrawable",
                                              "glXSwapBuffers",
                                              "eglSwapBuffers",
                                              "eglMakeCurrent",
                                              "eglGetProcAddress",
                                              "eglCreateContext",
                                              "eglGetDisplay",
                                              "eglInitialize",
                                              "eglChooseConfig",
                                              "eglCreateWindowSurface",
                                              "eglBindAPI",
                                              "eglQueryString",
                                              "eglGetConfigAttrib",
                                              "eglDestroyContext",
                                              "eglDestroySurface",
                                              "eglGetPlatformDisplay",
                                              "eglGetPlatformDisplayEXT",
                                              "eglCreatePbufferSurface",
                                              "eglCreatePlatformWindowSurface",
                                              "eglCreatePlatformWindowSurfaceEXT",
                                              "eglGetConfigs",
                                              "eglQuerySurface",
                                              "eglQueryContext",
                                              "eglGetCurrentContext",
                                              "eglGetCurrentDisplay",
                                              "eglGetCurrentSurface",
                                              "eglQueryDevicesEXT",
                                              "eglQueryDeviceStringEXT",
                                              "eglQueryDisplayAttribEXT",
                                              "eglReleaseThread",
                                              "eglWaitClient",
                                              "eglWaitGL",
                                              "eglWaitNative",
                                              "eglTerminate",
                                              "eglSwapInterval",
                                              "eglGetError"};
  return names;
}

struct ClientArray {
  bool enabled = false;
  int size = 4;
  int64_t type = GL_FLOAT;
  int stride = 0;
  std::string data;  // the blob apitrace recorded (from the array's base)
  bool have_data = false;
};

struct GlTextureObject {
  std::map<int, MipLevel> levels;
  int64_t base_format = GL_RGBA;                                          // the internal format's base: what a sampler returns
  int64_t min_filter = GL_NEAREST_MIPMAP_LINEAR, mag_filter = GL_LINEAR;  // OpenGL's defaults
  int64_t wrap_s = GL_REPEAT, wrap_t = GL_REPEAT;
  int scene_index = -1;  // the Scene texture of its current contents; -1: changed since
  int version = 0;
  bool depth = false;  // a depth texture (a shadow map's target)
  // glGenerateMipmap made its levels from the base level: oovr builds them
  // as it builds any chain (a box filter; OpenGL leaves the filter to the
  // implementation), with no note.
  bool generated = false;
};

struct ImmediateVertex {
  Vec4 position;
  Vec2 uv[kUnits];
  uint32_t colour;
};

// A texture unit's environment: its mode and, for GL_COMBINE, the
// combiner's functions, sources, operands and scales (OpenGL 1.3's
// defaults).
struct TexEnv {
  int64_t mode = GL_MODULATE;
  int64_t combine[2] = {GL_MODULATE, GL_MODULATE};  // RGB, alpha
  int64_t source[2][3] = {{GL_TEXTURE, GL_PREVIOUS, GL_CONSTANT}, {GL_TEXTURE, GL_PREVIOUS, GL_CONSTANT}};
  int64_t operand[2][3] = {{GL_SRC_COLOR, GL_SRC_COLOR, GL_SRC_ALPHA}, {GL_SRC_ALPHA, GL_SRC_ALPHA, GL_SRC_ALPHA}};
  float scale[2] = {1, 1};
};

// One layer of a draw's pass: the scene texture, its coordinates and how
// it combines (scene/material.h).
struct LayerKey {
  int texture = -1;
  TexCoords coords = TexCoords::surface;
  Combine combine = Combine::modulate;
  float scale = 1;
  LayerKind kind = LayerKind::diffuse;  // a fetch layer's (others: the first diffuse, the rest lightmap)
  auto tie() const { return std::tie(texture, coords, combine, scale, kind); }
  bool operator<(const LayerKey& o) const { return tie() < o.tie(); }
};

// What decides a draw's material (Material and Pass), compared whole.
struct MaterialKey {
  std::vector<LayerKey> layers;
  std::array<float, 4> colour{1, 1, 1, 1};  // the pass colour
  int64_t src = GL_ONE, dst = GL_ZERO;
  int64_t alpha_func = GL_ALWAYS;
  float alpha_ref = 0;
  int64_t depth_func = GL_ALWAYS;
  bool depth_write = false, colour_write = true;
  int cull = 0;  // 0 none, 1 back, 2 front
  float offset_factor = 0, offset_units = 0;
  auto tie() const {
    return std::tie(layers, colour, src, dst, alpha_func, alpha_ref, depth_func, depth_write, colour_write, cull, offset_factor,
                    offset_units);
  }
  bool operator<(const MaterialKey& o) const { return tie() < o.tie(); }
};

uint64_t fnv(const void* data, size_t n, uint64_t h = 1469598103934665603ull) {
  const auto* p = static_cast<const uint8_t*>(data);
  for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

// A value of type T from unaligned bytes (little-endian, as apitrace records them).
template <class T>
T load(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

uint32_t pack_colour(float r, float g, float b, float a) {
  const auto c = [](float v) { return uint32_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
  return c(r) | c(g) << 8 | c(b) << 16 | c(a) << 24;
}

class Interpreter {
 public:
  Interpreter(apitrace::Reader& reader, const GlTraceWindow& w) : m_reader(reader), m_window(w) {
    m_scene.name = "trace:" + reader.name();
    m_scene.description =
        "frames " + std::to_string(w.first) + " to " + std::to_string(w.first + w.count - 1) + " of an apitrace capture";
  }

  Scene run(GlTraceStats* stats) {
    if (m_window.first < 0 || m_window.count < 1)
      throw Error("a window of frames must start at 0 or later and hold at least one frame");
    if (!(m_window.metres_per_unit > 0 && std::isfinite(m_window.metres_per_unit)))
      throw Error("metres per unit must be a positive number");
    // Before the window only texture uploads need their data: every draw
    // is preceded by the client arrays it uses (apitrace's fake calls).
    const auto upload = [](const apitrace::FunctionSig& f) {
      return f.name == "glTexImage2D" || f.name == "glTexSubImage2D" || f.name == "glBufferData" || f.name == "glBufferSubData" ||
             f.name == "glBufferDataARB" || f.name == "glBufferSubDataARB";
    };
    if (m_window.first > 0) m_reader.read_blobs_of(upload);
    Call c;
    while (m_frame < m_window.first + m_window.count && m_reader.next(c)) {
      ++m_stats.calls;
      m_call = &c;
      try {
        interpret(c);
      } catch (const Error& e) {
        throw Error(where() + e.what());
      }
      if (c.ends_frame()) {
        end_frame();
        if (m_frame == m_window.first) m_reader.read_blobs_of(nullptr);  // every blob from here
      }
    }
    const int got = m_frame - m_window.first;
    if (got < m_window.count) {
      if (m_frame <= m_window.first)
        throw Error("apitrace file '" + m_reader.name() + "' has " + std::to_string(m_frame) + " frames, so frame " +
                    std::to_string(m_window.first) + " does not exist");
      throw Error("apitrace file '" + m_reader.name() + "' has " + std::to_string(m_frame) + " frames: frames " +
                  std::to_string(m_window.first) + " to " + std::to_string(m_window.first + m_window.count - 1) +
                  " reach past its end");
    }
    m_scene.camera.frames.assign(size_t(m_window.count), CameraPose{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}});
    m_scene.metres_per_unit = m_window.metres_per_unit;
    m_scene.capture_first_frame = m_window.first;
    m_scene.capture_width = m_window_w;
    m_scene.capture_height = m_window_h;
    m_scene.notes.push_back("the game's units taken as " + std::to_string(m_window.metres_per_unit) +
                            " m for the eyes' offsets; each eye sees the game's whole view, scaled to its viewport");
    if (m_incomplete)
      m_scene.notes.push_back(std::to_string(m_incomplete) +
                              " draws had a texture unit enabled with no image bound (OpenGL draws them untextured)");
    if (m_composites)
      m_scene.notes.push_back(
          std::to_string(m_composites) +
          " draws copied the view, rendered into a texture, into the window: the view's own draws stand for them");
    if (m_uneven_models)
      m_scene.notes.push_back(std::to_string(m_uneven_models) +
                              " draws of unevenly scaled models split with the view's projection (stereo re-projection)");
    for (const auto& [what, n] : m_approximated)
      m_scene.notes.push_back(std::to_string(n) + " draws through programs approximated (" + what + ")");
    if (m_unit1_alone) m_scene.notes.push_back("some draws textured from the second unit alone: drawn as the first layer");
    if (m_low_bit_uploads)
      m_scene.notes.push_back(std::to_string(m_low_bit_uploads) +
                              " texture uploads asked for fewer than 8 bits a channel; oovr keeps 8");
    if (m_compressed_uploads)
      m_scene.notes.push_back(std::to_string(m_compressed_uploads) +
                              " texture uploads asked the driver to compress them (S3TC); oovr keeps 8 bits a channel");
    if (m_filter_notes)
      m_scene.notes.push_back(std::to_string(m_filter_notes) +
                              " textures asked for nearest-texel or nearest-level filtering, drawn with linear filtering "
                              "(trilinear where mipmapped)");
    if (m_clamp_notes)
      m_scene.notes.push_back("GL_CLAMP drawn as GL_CLAMP_TO_EDGE (no border texels) on " + std::to_string(m_clamp_notes) +
                              " textures");
    if (m_mip_notes)
      m_scene.notes.push_back(std::to_string(m_mip_notes) +
                              " textures sampled with mipmaps were uploaded without all their levels; "
                              "oovr built the missing ones");
    m_stats.frames_in_trace = uint64_t(m_frame);
    if (stats) *stats = m_stats;
    m_scene.validate();
    return std::move(m_scene);
  }

 private:
  std::string where() const {
    return "apitrace file '" + m_reader.name() + "', frame " + std::to_string(m_frame) + ", call " +
           std::to_string(m_call ? m_call->no : 0) + " " + (m_call ? m_call->name() : std::string()) + ": ";
  }
  bool in_window() const { return m_frame >= m_window.first; }

  static int64_t num(const Call& c, size_t i) { return c.arg(i).integer(); }
  static float real(const Call& c, size_t i) { return float(c.arg(i).number()); }
  [[noreturn]] static void unsupported(const std::string& what) {
    throw Error(what + ", which oovr's OpenGL interpreter does not model");
  }

  Mat4& matrix() {
    auto& stack = m_mode == GL_PROJECTION ? m_projection : m_mode == GL_TEXTURE ? m_texture_matrix : m_modelview;
    return stack.back();
  }
  std::vector<Mat4>& stack() {
    return m_mode == GL_PROJECTION ? m_projection : m_mode == GL_TEXTURE ? m_texture_matrix : m_modelview;
  }

  static Mat4 matrix_arg(const Call& c, size_t i) {
    const Value& v = c.arg(i);
    if (v.kind != Value::Kind::array || v.items.size() != 16) throw Error("a matrix that is not 16 numbers");
    Mat4 m;
    for (int k = 0; k < 16; ++k) m.m[k / 4][k % 4] = float(v.items[size_t(k)].number());
    return m;
  }

  void set_cap(int64_t cap, bool on) {
    if (cap == GL_TEXTURE_2D) {
      m_texture_2d[m_unit] = on;
    } else if (cap >= GL_CLIP_PLANE0 && cap < GL_CLIP_PLANE0 + 6) {
      m_refused[cap] = on ? "a user clip plane (GL_CLIP_PLANEi)" : "";
    } else if (cap >= GL_TEXTURE_GEN_S && cap <= GL_TEXTURE_GEN_Q) {
      m_refused[cap + 0x10000 * m_unit] = on ? "texture coordinate generation (GL_TEXTURE_GEN)" : "";
    } else if (cap >= GL_LIGHT0 && cap <= GL_LIGHT7) {
      // Lights matter only with GL_LIGHTING, which is refused.
    } else {
      switch (cap) {
        case GL_BLEND: m_blend = on; break;
        case GL_ALPHA_TEST: m_alpha_test = on; break;
        case GL_DEPTH_TEST: m_depth_test = on; break;
        case GL_CULL_FACE: m_cull = on; break;
        case GL_POLYGON_OFFSET_FILL: m_offset = on; break;
        case GL_SCISSOR_TEST: m_scissor_test = on; break;
        case GL_FOG: m_refused[cap] = on ? "fog (GL_FOG)" : ""; break;
        case GL_LIGHTING: m_refused[cap] = on ? "fixed-function lighting (GL_LIGHTING)" : ""; break;
        case GL_STENCIL_TEST: m_refused[cap] = on ? "the stencil test" : ""; break;
        case GL_LINE_STIPPLE:
        case GL_LINE_SMOOTH:
        case GL_POINT_SMOOTH:
        case GL_DITHER:
        case GL_MULTISAMPLE:
        case GL_NORMALIZE:
        case GL_RESCALE_NORMAL:
        case GL_COLOR_MATERIAL: break;  // no effect on filled, unlit, single-sampled triangles
        default:
          if (on) m_refused[cap] = "capability " + std::to_string(cap) + " enabled";
          else m_refused[cap].clear();
      }
    }
  }

  ClientArray& client_array(int64_t which) {
    switch (which) {
      case GL_VERTEX_ARRAY: return m_vertex;
      case GL_COLOR_ARRAY: return m_colour_array;
      case GL_TEXTURE_COORD_ARRAY: return m_texcoord[m_client_unit];
      case GL_NORMAL_ARRAY: return m_normal;
      default: unsupported("client array " + std::to_string(which));
    }
  }

  void set_pointer(ClientArray& a, const Call& c, bool has_size) {
    size_t i = 0;
    a.size = has_size ? int(num(c, i++)) : 3;
    a.type = num(c, i++);
    a.stride = int(num(c, i++));
    const Value& p = c.arg(i);
    if (p.kind == Value::Kind::blob && !p.skipped) {
      a.data = p.bytes;
      a.have_data = true;
    } else {
      // A pointer into a buffer object, or a pointer apitrace did not
      // record because no draw used it yet.
      a.data.clear();
      a.have_data = false;
    }
    if (a.size < 1 || a.size > 4 || a.stride < 0) throw Error("a client array of size " + std::to_string(a.size));
  }

  void interpret(const Call& c) {
    const std::string& n = c.name();
    if (n == "glEnable" || n == "glDisable") {
      set_cap(num(c, 0), n == "glEnable");
    } else if (n == "glEnableClientState" || n == "glDisableClientState") {
      client_array(num(c, 0)).enabled = n == "glEnableClientState";
    } else if (n == "glVertexPointer") {
      set_pointer(m_vertex, c, true);
    } else if (n == "glColorPointer") {
      set_pointer(m_colour_array, c, true);
    } else if (n == "glTexCoordPointer") {
      set_pointer(m_texcoord[m_client_unit], c, true);
    } else if (n == "glNormalPointer") {
      set_pointer(m_normal, c, false);
    } else if (n == "glActiveTexture" || n == "glActiveTextureARB") {
      m_unit = select_unit(num(c, 0), false);
      m_active_unit = int(num(c, 0) - GL_TEXTURE0);
    } else if (n == "glClientActiveTexture" || n == "glClientActiveTextureARB") {
      m_client_unit = select_unit(num(c, 0), true);
    } else if (n == "glMatrixMode") {
      m_mode = num(c, 0);
      if (m_mode != GL_MODELVIEW && m_mode != GL_PROJECTION && m_mode != GL_TEXTURE)
        throw Error("matrix mode " + std::to_string(m_mode));
    } else if (n == "glLoadMatrixf" || n == "glLoadMatrixd") {
      matrix() = matrix_arg(c, 0);
    } else if (n == "glMultMatrixf" || n == "glMultMatrixd") {
      matrix() = matrix() * matrix_arg(c, 0);
    } else if (n == "glLoadIdentity") {
      matrix() = Mat4::identity();
    } else if (n == "glPushMatrix") {
      if (stack().size() >= 64) throw Error("more than 64 matrices pushed");
      stack().push_back(stack().back());
    } else if (n == "glPopMatrix") {
      if (stack().size() <= 1) throw Error("a matrix popped from an empty stack");
      stack().pop_back();
    } else if (n == "glTranslatef" || n == "glTranslated") {
      matrix() = matrix() * translate({real(c, 0), real(c, 1), real(c, 2)});
    } else if (n == "glScalef" || n == "glScaled") {
      matrix() = matrix() * scale({real(c, 0), real(c, 1), real(c, 2)});
    } else if (n == "glRotatef" || n == "glRotated") {
      const Vec3 axis = normalize(Vec3{real(c, 1), real(c, 2), real(c, 3)});
      matrix() = matrix() * rotate(axis, radians(real(c, 0)));
    } else if (n == "glOrtho") {
      const double l = c.arg(0).number(), r = c.arg(1).number(), b = c.arg(2).number(), t = c.arg(3).number(),
                   nv = c.arg(4).number(), f = c.arg(5).number();
      if (l == r || b == t || nv == f) throw Error("a degenerate orthographic projection");
      Mat4 o;
      o.at(0, 0) = float(2 / (r - l));
      o.at(1, 1) = float(2 / (t - b));
      o.at(2, 2) = float(-2 / (f - nv));
      o.at(0, 3) = float(-(r + l) / (r - l));
      o.at(1, 3) = float(-(t + b) / (t - b));
      o.at(2, 3) = float(-(f + nv) / (f - nv));
      matrix() = matrix() * o;
    } else if (n == "glFrustum") {
      const double l = c.arg(0).number(), r = c.arg(1).number(), b = c.arg(2).number(), t = c.arg(3).number(),
                   nv = c.arg(4).number(), f = c.arg(5).number();
      if (l == r || b == t || nv == f || nv <= 0) throw Error("a degenerate perspective projection");
      Mat4 p;
      p.at(0, 0) = float(2 * nv / (r - l));
      p.at(1, 1) = float(2 * nv / (t - b));
      p.at(0, 2) = float((r + l) / (r - l));
      p.at(1, 2) = float((t + b) / (t - b));
      p.at(2, 2) = float(-(f + nv) / (f - nv));
      p.at(2, 3) = float(-2 * f * nv / (f - nv));
      p.at(3, 2) = -1;
      p.at(3, 3) = 0;
      matrix() = matrix() * p;
    } else if (n == "glViewport") {
      m_viewport = {int(num(c, 0)), int(num(c, 1)), int(num(c, 2)), int(num(c, 3))};
      if (m_viewport[2] <= 0 || m_viewport[3] <= 0 || m_viewport[2] > 16384 || m_viewport[3] > 16384)
        throw Error("a viewport of " + std::to_string(m_viewport[2]) + "x" + std::to_string(m_viewport[3]));
      // The window is the largest viewport the game sets (it sets the
      // whole window for its 2-D pass every frame), into the window or a
      // framebuffer object with a colour texture (the view rendered into a
      // texture), not into a shadow map's.
      if (draws_colour()) {
        m_window_w = std::max(m_window_w, m_viewport[0] + m_viewport[2]);
        m_window_h = std::max(m_window_h, m_viewport[1] + m_viewport[3]);
      }
    } else if (n == "glScissor") {
      m_scissor = {int(num(c, 0)), int(num(c, 1)), int(num(c, 2)), int(num(c, 3))};
    } else if (n == "glDepthRange" || n == "glDepthRangef") {
      m_depth_near = std::clamp(float(c.arg(0).number()), 0.0f, 1.0f);
      m_depth_far = std::clamp(float(c.arg(1).number()), 0.0f, 1.0f);
    } else if (n == "glBlendFunc") {
      m_src = num(c, 0);
      m_dst = num(c, 1);
    } else if (n == "glAlphaFunc") {
      m_alpha_func = num(c, 0);
      m_alpha_ref = std::clamp(real(c, 1), 0.0f, 1.0f);
    } else if (n == "glDepthFunc") {
      m_depth_func = num(c, 0);
    } else if (n == "glDepthMask") {
      m_depth_mask = num(c, 0) != 0;
    } else if (n == "glColorMask") {
      m_colour_mask = {num(c, 0) != 0, num(c, 1) != 0, num(c, 2) != 0, num(c, 3) != 0};
    } else if (n == "glCullFace") {
      m_cull_face = num(c, 0);
    } else if (n == "glFrontFace") {
      m_front_face = num(c, 0);
    } else if (n == "glPolygonOffset") {
      m_offset_factor = real(c, 0);
      m_offset_units = real(c, 1);
    } else if (n == "glPolygonMode") {
      m_polygon_mode = num(c, 1);
    } else if (n == "glShadeModel") {
      m_shade_model = num(c, 0);
    } else if (n == "glDrawBuffer") {
      m_draw_buffer = num(c, 0);
    } else if (n == "glColor3f" || n == "glColor3d") {
      m_colour = pack_colour(real(c, 0), real(c, 1), real(c, 2), 1);
    } else if (n == "glColor4f" || n == "glColor4d") {
      m_colour = pack_colour(real(c, 0), real(c, 1), real(c, 2), real(c, 3));
    } else if (n == "glColor3ub") {
      m_colour = uint32_t(num(c, 0) & 255) | uint32_t(num(c, 1) & 255) << 8 | uint32_t(num(c, 2) & 255) << 16 | 0xFF000000u;
    } else if (n == "glColor4ub") {
      m_colour = uint32_t(num(c, 0) & 255) | uint32_t(num(c, 1) & 255) << 8 | uint32_t(num(c, 2) & 255) << 16 |
                 uint32_t(num(c, 3) & 255) << 24;
    } else if (n == "glColor3fv" || n == "glColor4fv" || n == "glColor3ubv" || n == "glColor4ubv") {
      const Value& v = c.arg(0);
      const bool ub = n.find("ub") != std::string::npos;
      const size_t k = n[7] == '3' ? 3 : 4;
      if (v.kind != Value::Kind::array || v.items.size() < k)
        throw Error("a colour of fewer than " + std::to_string(k) + " numbers");
      float f[4] = {1, 1, 1, 1};
      for (size_t i = 0; i < k; ++i) f[i] = float(v.items[i].number()) / (ub ? 255.0f : 1.0f);
      m_colour = pack_colour(f[0], f[1], f[2], f[3]);
    } else if (n == "glTexCoord2f" || n == "glTexCoord2d") {
      m_texcoord_now[0] = {real(c, 0), real(c, 1)};
    } else if (n == "glTexCoord2fv") {
      m_texcoord_now[0] = vec2_arg(c, 0);
    } else if (n == "glMultiTexCoord2f" || n == "glMultiTexCoord2fARB") {
      const int u = select_unit(num(c, 0), false);
      m_texcoord_now[u] = {real(c, 1), real(c, 2)};
    } else if (n == "glMultiTexCoord2fv" || n == "glMultiTexCoord2fvARB") {
      const int u = select_unit(num(c, 0), false);
      m_texcoord_now[u] = vec2_arg(c, 1);
    } else if (n == "glBegin") {
      if (m_in_begin) throw Error("glBegin inside glBegin");
      m_in_begin = true;
      m_begin_mode = num(c, 0);
      m_immediate.clear();
    } else if (n == "glEnd") {
      if (!m_in_begin) throw Error("glEnd without glBegin");
      m_in_begin = false;
      immediate_draw();
    } else if (n == "glVertex2f" || n == "glVertex2d" || n == "glVertex2i" || n == "glVertex2s") {
      vertex({real(c, 0), real(c, 1), 0, 1});
    } else if (n == "glVertex3f" || n == "glVertex3d") {
      vertex({real(c, 0), real(c, 1), real(c, 2), 1});
    } else if (n == "glVertex3fv" || n == "glVertex2fv") {
      const Value& v = c.arg(0);
      const size_t k = n[8] == '3' ? 3 : 2;
      if (v.kind != Value::Kind::array || v.items.size() < k)
        throw Error("a vertex of fewer than " + std::to_string(k) + " numbers");
      vertex({float(v.items[0].number()), float(v.items[1].number()), k == 3 ? float(v.items[2].number()) : 0.0f, 1});
    } else if (n == "glDrawElements" || n == "glDrawRangeElements") {
      const bool range = n == "glDrawRangeElements";
      const int64_t count = num(c, range ? 3 : 1);
      if (count < 0 || count > (int64_t(1) << 26)) throw Error("a draw of " + std::to_string(count) + " indices");
      if (m_program == 0) indexed_draw(num(c, 0), count, num(c, range ? 4 : 2), c.arg(range ? 5 : 3));
      else if (in_window() && count > 0)
        program_draw(num(c, 0), program_indices(count, num(c, range ? 4 : 2), c.arg(range ? 5 : 3)));
    } else if (n == "glDrawArrays") {
      const int64_t first = num(c, 1), count = num(c, 2);
      if (first < 0 || count < 0 || count > (int64_t(1) << 24))
        throw Error("a draw of " + std::to_string(count) + " vertices from " + std::to_string(first));
      if (in_window() && count > 0) {
        // Client arrays are checked before anything the draw's size is allocated.
        if (m_program == 0) check_vertex(uint64_t(first + count - 1));
        std::vector<uint32_t> element(static_cast<size_t>(count));
        for (int64_t i = 0; i < count; ++i) element[size_t(i)] = uint32_t(first + i);
        if (m_program == 0) array_vertices(num(c, 0), element);
        else program_draw(num(c, 0), element);
      }
    } else if (n == "glClear") {
      clear(uint64_t(num(c, 0)));
    } else if (n == "glBindTexture") {
      // Other targets (cube maps, 3-D textures) are bound and uploaded
      // without effect: no draw oovr takes samples them (a program that
      // does is refused, and GL_TEXTURE_CUBE_MAP enabled is refused).
      if (num(c, 0) == GL_TEXTURE_2D) m_unit_texture[m_active_unit] = uint32_t(num(c, 1));
    } else if (n == "glTexImage2D") {
      tex_image(c, false);
    } else if (n == "glTexSubImage2D") {
      tex_image(c, true);
    } else if (n == "glTexParameterf" || n == "glTexParameteri") {
      if (num(c, 0) == GL_TEXTURE_2D) tex_parameter(num(c, 1), c.arg(2).number());
    } else if (n == "glTexParameterfv" || n == "glTexParameteriv") {
      const Value& v = c.arg(2);
      if (v.kind != Value::Kind::array || v.items.empty()) throw Error("a texture parameter without a value");
      if (num(c, 0) == GL_TEXTURE_2D) tex_parameter(num(c, 1), v.items[0].number());
    } else if (n == "glTexEnvf" || n == "glTexEnvi") {
      tex_env(num(c, 0), num(c, 1), c.arg(2).number());
    } else if (n == "glPixelStorei" || n == "glPixelStoref") {
      const int64_t p = num(c, 0);
      const int64_t v = int64_t(c.arg(1).number());
      if (p == GL_UNPACK_ALIGNMENT) m_unpack_alignment = int(v);
      else if (p == GL_UNPACK_ROW_LENGTH) m_unpack_row_length = int(v);
      else if (p == GL_UNPACK_SKIP_ROWS) m_unpack_skip_rows = int(v);
      else if (p == GL_UNPACK_SKIP_PIXELS) m_unpack_skip_pixels = int(v);
      if (m_unpack_alignment != 1 && m_unpack_alignment != 2 && m_unpack_alignment != 4 && m_unpack_alignment != 8)
        throw Error("an unpack alignment of " + std::to_string(m_unpack_alignment));
      if (m_unpack_row_length < 0 || m_unpack_skip_rows < 0 || m_unpack_skip_pixels < 0)
        throw Error("a negative unpack parameter");
    } else if (n == "glBindBuffer" || n == "glBindBufferARB") {
      const int64_t target = num(c, 0);
      const auto id = uint32_t(num(c, 1));
      if (target == GL_ARRAY_BUFFER) m_array_buffer = id;
      else if (target == GL_ELEMENT_ARRAY_BUFFER) m_element_buffer = id;
    } else if (glsl_call(c)) {
      // OpenGL 3 buffers, vertex attributes, programs and framebuffers.
    } else if (n == "memcpy") {
      // Data written to a mapped buffer (fake): buffers are refused at draw time.
    } else if (harmless_calls().count(n)) {
      // No effect on what is drawn.
    } else {
      unsupported("a call (" + n + ")");
    }
  }

  // glTexEnv: the mode, and the combiner's state for GL_COMBINE (resolved
  // at the draw, resolve_env). Anything else (GL_TEXTURE_ENV_COLOR, LOD
  // bias, point sprites) is refused at the draw.
  void tex_env(int64_t target, int64_t pname, double value) {
    TexEnv& e = m_env[m_unit];
    const auto v = int64_t(value);
    if (target == GL_TEXTURE_ENV && pname == GL_TEXTURE_ENV_MODE) {
      e.mode = v;
    } else if (target == GL_TEXTURE_ENV && (pname == GL_COMBINE_RGB || pname == GL_COMBINE_ALPHA)) {
      e.combine[pname - GL_COMBINE_RGB] = v;
    } else if (target == GL_TEXTURE_ENV && pname >= GL_SRC0_RGB && pname < GL_SRC0_ALPHA + 3 &&
               (pname < GL_SRC0_RGB + 3 || pname >= GL_SRC0_ALPHA)) {
      const bool a = pname >= GL_SRC0_ALPHA;
      e.source[a][pname - (a ? GL_SRC0_ALPHA : GL_SRC0_RGB)] = v;
    } else if (target == GL_TEXTURE_ENV && pname >= GL_OPERAND0_RGB && pname < GL_OPERAND0_ALPHA + 3 &&
               (pname < GL_OPERAND0_RGB + 3 || pname >= GL_OPERAND0_ALPHA)) {
      const bool a = pname >= GL_OPERAND0_ALPHA;
      e.operand[a][pname - (a ? GL_OPERAND0_ALPHA : GL_OPERAND0_RGB)] = v;
    } else if (target == GL_TEXTURE_ENV && pname == GL_RGB_SCALE) {
      e.scale[0] = float(value);
    } else if (target == GL_TEXTURE_ENV && pname == GL_ALPHA_SCALE) {
      e.scale[1] = float(value);
    } else {
      m_refused[0x70000 + m_unit] =
          "texture environment parameter " + std::to_string(pname) + " of target " + std::to_string(target);
    }
  }

  // Unit `u`'s environment as oovr's layer combines (scene/material.h):
  // its mode, or a GL_COMBINE that computes one of them. `first`: the
  // first enabled unit (its GL_PREVIOUS is the primary colour); `last`:
  // no enabled unit follows (OpenGL clamps each unit's result to [0, 1],
  // oovr's layers only the end, so a scale > 1 is taken only last);
  // `opaque`: the texture's alpha is 1 everywhere.
  std::pair<int64_t, float> resolve_env(int u, bool first, bool last, bool opaque) const {
    const TexEnv& e = m_env[u];
    if (e.mode != GL_COMBINE) return {e.mode, 1.0f};
    const auto describe = [&](const std::string& what) {
      unsupported("a GL_COMBINE texture environment on unit " + std::to_string(u) + " with " + what);
    };
    const auto previous = [&](int64_t src) { return src == GL_PREVIOUS || (first && src == GL_PRIMARY_COLOR); };
    // Which of the texel (T) and the previous colour (P) argument k is, or 0.
    const auto arg = [&](int ch, int k) -> char {
      const int64_t want = ch == 0 ? GL_SRC_COLOR : GL_SRC_ALPHA;
      if (e.operand[ch][k] != want) return 0;
      if (e.source[ch][k] == GL_TEXTURE || e.source[ch][k] == GL_TEXTURE0 + u) return 'T';
      return previous(e.source[ch][k]) ? 'P' : 0;
    };
    // The function each channel computes: modulate (T x P), add (T + P),
    // replace (T) or keep (P).
    const auto function = [&](int ch) -> char {
      const char a0 = arg(ch, 0), a1 = arg(ch, 1);
      switch (e.combine[ch]) {
        case GL_MODULATE: return (a0 == 'T' && a1 == 'P') || (a0 == 'P' && a1 == 'T') ? 'm' : 0;
        case GL_ADD: return (a0 == 'T' && a1 == 'P') || (a0 == 'P' && a1 == 'T') ? 'a' : 0;
        case GL_REPLACE: return a0 == 'T' ? 'r' : a0 == 'P' ? 'k' : 0;
        default: return 0;
      }
    };
    const char rgb = function(0), alpha = function(1);
    if (!rgb || !alpha) describe("functions or sources other than the texel and the previous colour");
    if (e.scale[1] != 1.0f) describe("an alpha scale");
    if (e.scale[0] != 1.0f && e.scale[0] != 2.0f && e.scale[0] != 4.0f) describe("an RGB scale other than 1, 2 or 4");
    if (e.scale[0] != 1.0f && (rgb != 'm' || !last))
      describe("an RGB scale on " + std::string(rgb != 'm' ? "a sum or a replacement" : "a unit before another"));
    // oovr's alpha: modulated by a later layer's texel, replaced by a
    // replacing first layer; keeping the previous alpha is the same when
    // the texel's alpha is 1.
    const char want_alpha = rgb == 'r' ? 'r' : 'm';
    if (alpha != want_alpha && !(alpha == 'k' && opaque)) describe("an alpha function unlike its colour function's");
    switch (rgb) {
      case 'm': return {GL_MODULATE, e.scale[0]};
      case 'a': return {GL_ADD, 1.0f};
      case 'r': return {GL_REPLACE, 1.0f};
      default: describe("the previous colour passed through");
    }
    return {};
  }

  // ---- OpenGL 3 and GLSL (docs/real-frames.md, "GLSL games") ----

  // The OpenGL 3 calls: buffer objects, vertex attributes, shaders,
  // programs and their uniforms, framebuffer objects. False: not one.
  bool glsl_call(const Call& c) {
    static const std::set<std::string> harmless = {"glGenBuffers",
                                                   "glGenVertexArrays",
                                                   "glGenFramebuffers",
                                                   "glGenRenderbuffers",
                                                   "glBindRenderbuffer",
                                                   "glRenderbufferStorage",
                                                   "glFramebufferRenderbuffer",
                                                   "glCheckFramebufferStatus",
                                                   "glDeleteFramebuffers",
                                                   "glDeleteRenderbuffers",
                                                   "glCompileShader",
                                                   "glGetShaderiv",
                                                   "glGetShaderInfoLog",
                                                   "glDeleteShader",
                                                   "glGetProgramiv",
                                                   "glGetProgramInfoLog",
                                                   "glBindFragDataLocation",
                                                   "glGetUniformBlockIndex",
                                                   "glUniformBlockBinding",
                                                   "glValidateProgram",
                                                   "glDetachShader",
                                                   "glGetAttribLocation",
                                                   "glGetActiveUniform",
                                                   "glGetActiveAttrib",
                                                   "glDrawBuffers",
                                                   "glDebugMessageControl",
                                                   "glDebugMessageControlARB",
                                                   "glDebugMessageCallback",
                                                   "glDebugMessageCallbackARB"};
    const std::string& n = c.name();
    if (harmless.count(n)) return true;
    if (n == "glDeleteBuffers") {
      const Value& v = c.arg(1);
      if (v.kind == Value::Kind::array)
        for (const Value& id : v.items) {
          const auto it = m_buffers.find(uint32_t(id.integer()));
          if (it == m_buffers.end()) continue;
          m_buffer_bytes -= it->second.size();
          m_buffers.erase(it);
        }
    } else if (n == "glBufferData" || n == "glBufferDataARB") {
      std::string& b = buffer(num(c, 0));
      const int64_t size = num(c, 1);
      const InputLimits& lim = InputLimits::get();
      if (size < 0) throw Error("a buffer of " + std::to_string(size) + " bytes");
      m_buffer_bytes -= b.size();
      m_buffer_bytes += uint64_t(size);
      check_limit(m_buffer_bytes, lim.scene_bytes, "scene_bytes", "the capture's buffer objects", "bytes");
      const Value& data = c.arg(2);
      if (data.kind == Value::Kind::blob && data.bytes.size() >= uint64_t(size)) b.assign(data.bytes, 0, size_t(size));
      else if (data.kind == Value::Kind::blob && !data.skipped) throw Error("buffer data shorter than its size");
      else b.assign(size_t(size), '\0');
    } else if (n == "glBufferSubData" || n == "glBufferSubDataARB") {
      std::string& b = buffer(num(c, 0));
      const int64_t offset = num(c, 1), size = num(c, 2);
      const Value& data = c.arg(3);
      if (offset < 0 || size < 0 || uint64_t(offset) + uint64_t(size) > b.size())
        throw Error("buffer data at " + std::to_string(offset) + " of " + std::to_string(size) + " bytes, outside a buffer of " +
                    std::to_string(b.size()));
      if (data.kind == Value::Kind::blob && !data.skipped) {
        if (data.bytes.size() < uint64_t(size)) throw Error("buffer data shorter than its size");
        b.replace(size_t(offset), size_t(size), data.bytes, 0, size_t(size));
      }
    } else if (n == "glBindVertexArray") {
      // A vertex array object holds the attributes' arrays and the element
      // buffer binding (ioquake3's opengl2 binds one per model and
      // surface): the current ones are saved under the object left and
      // those of the object bound are restored (a new object's are unset).
      const auto id = uint32_t(num(c, 0));
      if (id == m_vao) return true;
      if (m_vaos.size() >= kMaxVertexArrays && !m_vaos.count(id))
        throw Error("more than " + std::to_string(kMaxVertexArrays) + " vertex array objects");
      VertexArrayObject& left = m_vaos[m_vao];
      left.attribs = m_attribs;
      left.element_buffer = m_element_buffer;
      // Client-memory arrays keep no data in the object: apitrace records
      // their data again before every draw that reads them, and a hostile
      // capture could otherwise hold a blob in each of thousands of objects.
      for (VertexAttrib& a : left.attribs)
        if (a.buffer == 0) {
          a.array.data = std::string();
          a.array.have_data = false;
        }
      const VertexArrayObject& bound = m_vaos[id];
      m_attribs = bound.attribs;
      m_element_buffer = bound.element_buffer;
      m_vao = id;
    } else if (n == "glDeleteVertexArrays") {
      const Value& v = c.arg(1);
      if (v.kind == Value::Kind::array)
        for (const Value& id : v.items) {
          const auto vao = uint32_t(id.integer());
          if (vao == 0) continue;
          m_vaos.erase(vao);
          if (vao == m_vao) {  // deleting the bound object binds 0
            m_attribs = m_vaos[0].attribs;
            m_element_buffer = m_vaos[0].element_buffer;
            m_vao = 0;
          }
        }
    } else if (n == "glVertexAttribPointer" || n == "glVertexAttribPointerARB") {
      VertexAttrib& a = attrib(num(c, 0));
      a.array.size = int(num(c, 1));
      a.array.type = num(c, 2);
      a.normalized = num(c, 3) != 0;
      a.array.stride = int(num(c, 4));
      if (a.array.size < 1 || a.array.size > 4 || a.array.stride < 0)
        throw Error("a vertex attribute of size " + std::to_string(a.array.size));
      const Value& p = c.arg(5);
      a.buffer = m_array_buffer;
      if (a.buffer != 0) {
        a.offset = uint64_t(p.integer());
        a.array.data.clear();
        a.array.have_data = false;
      } else if (p.kind == Value::Kind::blob && !p.skipped) {
        a.array.data = p.bytes;
        a.array.have_data = true;
      } else {
        a.array.data.clear();
        a.array.have_data = false;
      }
    } else if (n == "glEnableVertexAttribArray" || n == "glDisableVertexAttribArray") {
      attrib(num(c, 0)).enabled = n == "glEnableVertexAttribArray";
    } else if (n.rfind("glVertexAttrib", 0) == 0 && (n.size() == 16 || n.size() == 17) && n[14] >= '1' && n[14] <= '4' &&
               n[15] == 'f') {
      // glVertexAttrib{1,2,3,4}f[v]: the value of a disabled attribute.
      VertexAttrib& a = attrib(num(c, 0));
      const int k = n[14] - '0';
      float v[4] = {0, 0, 0, 1};
      if (n.size() == 17) {
        const Value& arr = c.arg(1);
        if (arr.kind != Value::Kind::array || arr.items.size() < size_t(k)) throw Error("a vertex attribute of too few numbers");
        for (int i = 0; i < k; ++i) v[i] = float(arr.items[size_t(i)].number());
      } else {
        for (int i = 0; i < k; ++i) v[i] = real(c, size_t(1 + i));
      }
      std::copy(v, v + 4, a.constant);
    } else if (n == "glCreateShader") {
      m_shader_sources[uint32_t(c.ret.integer())].clear();
    } else if (n == "glShaderSource") {
      auto& src = m_shader_sources[uint32_t(num(c, 0))];
      src.clear();
      const Value& strings = c.arg(2);
      const Value& lengths = c.arg(3);
      if (strings.kind != Value::Kind::array) throw Error("shader source that is not an array of strings");
      for (size_t i = 0; i < strings.items.size(); ++i) {
        std::string text = strings.items[i].bytes;
        if (lengths.kind == Value::Kind::array && i < lengths.items.size() && lengths.items[i].integer() >= 0)
          text.resize(std::min(text.size(), size_t(lengths.items[i].integer())));
        src.push_back(std::move(text));
      }
    } else if (n == "glCreateProgram") {
      m_programs[uint32_t(c.ret.integer())] = GlslProgram{};
    } else if (n == "glAttachShader") {
      program(num(c, 0)).shaders.push_back(uint32_t(num(c, 1)));
    } else if (n == "glBindAttribLocation") {
      const int64_t index = num(c, 1);
      (void)attrib(index);  // an index beyond the 16 attributes kept is an error here, not at a draw
      program(num(c, 0)).attributes[c.arg(2).bytes] = int(index);
    } else if (n == "glLinkProgram") {
      GlslProgram& p = program(num(c, 0));
      std::vector<std::vector<std::string>> sources;  // each attached shader's strings
      for (uint32_t sh : p.shaders)
        if (const auto it = m_shader_sources.find(sh); it != m_shader_sources.end()) sources.push_back(it->second);
      const auto darkplaces = [&] {
        std::set<std::string> defines;
        for (const auto& strings : sources) {
          const std::set<std::string> d = permutation_defines(strings);
          defines.insert(d.begin(), d.end());
        }
        return darkplaces_recipe(defines);
      };
      p.linked = true;
      try {
        p.recipe = is_ioq3_program(sources) ? ioq3_recipe(sources) : darkplaces();
        p.refusal.clear();
      } catch (const Error& e) {
        p.refusal = e.what();  // refused at its first draw
      }
    } else if (n == "glDeleteProgram") {
      m_programs.erase(uint32_t(num(c, 0)));
    } else if (n == "glUseProgram" || n == "glUseProgramObjectARB") {
      m_program = uint32_t(num(c, 0));
      if (m_program != 0) (void)program(m_program);
    } else if (n == "glGetUniformLocation") {
      const int64_t loc = c.ret.integer();
      if (loc >= 0) program(num(c, 0)).uniform_names[loc] = c.arg(1).bytes;
    } else if (n.rfind("glUniform", 0) == 0) {
      uniform(c);
    } else if (n == "glBindFramebuffer") {
      const int64_t target = num(c, 0);
      if (target == GL_FRAMEBUFFER || target == GL_DRAW_FRAMEBUFFER) m_fbo = uint32_t(num(c, 1));
    } else if (n == "glFramebufferTexture2D") {
      if (num(c, 1) == GL_COLOR_ATTACHMENT0) m_fbo_colour[m_fbo] = uint32_t(num(c, 3));
    } else if (n == "glGenerateMipmap" || n == "glGenerateMipmapEXT") {
      if (num(c, 0) != GL_TEXTURE_2D) return true;  // cube maps: not sampled by what oovr draws
      GlTextureObject& t = m_textures[m_unit_texture[size_t(m_active_unit)]];
      for (auto it = t.levels.begin(); it != t.levels.end();) {
        if (it->first == 0) {
          ++it;
          continue;
        }
        m_texel_bytes -= it->second.rgba.size();
        it = t.levels.erase(it);
      }
      t.generated = true;
      t.scene_index = -1;
    } else if (n == "glCopyTexSubImage2D" || n == "glCopyTexImage2D") {
      // The framebuffer copied into the bound texture: what it samples
      // then is the view (refused where it is drawn, as render-to-texture).
      if (num(c, 0) == GL_TEXTURE_2D) m_view_targets.insert(m_unit_texture[size_t(m_active_unit)]);
    } else if (n == "glBlendFuncSeparate") {
      m_src = num(c, 0);
      m_dst = num(c, 1);
      m_separate_alpha = num(c, 2) != m_src || num(c, 3) != m_dst;
    } else {
      return false;
    }
    return true;
  }

  std::string& buffer(int64_t target) {
    const uint32_t id = target == GL_ARRAY_BUFFER ? m_array_buffer : target == GL_ELEMENT_ARRAY_BUFFER ? m_element_buffer : 0;
    if (target != GL_ARRAY_BUFFER && target != GL_ELEMENT_ARRAY_BUFFER) unsupported("buffer target " + std::to_string(target));
    if (id == 0) throw Error("buffer data with no buffer object bound");
    return m_buffers[id];
  }

  struct VertexAttrib {
    bool enabled = false;
    ClientArray array;  // size, type, stride; the data when it is client memory
    bool normalized = false;
    uint32_t buffer = 0;               // the buffer object it reads (0: client memory)
    uint64_t offset = 0;               // into it
    float constant[4] = {0, 0, 0, 1};  // its value while disabled
  };
  VertexAttrib& attrib(int64_t index) {
    if (index < 0 || index >= int64_t(m_attribs.size())) throw Error("vertex attribute " + std::to_string(index));
    return m_attribs[size_t(index)];
  }

  struct GlslProgram {
    std::vector<uint32_t> shaders;
    std::map<std::string, int> attributes;               // glBindAttribLocation
    std::map<int64_t, std::string> uniform_names;        // glGetUniformLocation's answers
    std::map<std::string, std::vector<float>> uniforms;  // their values, by name
    bool linked = false;
    ProgramRecipe recipe;
    std::string refusal;  // why its draws are refused ("" none)
  };
  GlslProgram& program(int64_t id) {
    const auto it = m_programs.find(uint32_t(id));
    if (it == m_programs.end()) throw Error("program " + std::to_string(id) + ", which was not created");
    return it->second;
  }

  // glUniform{1,2,3,4}{f,i}[v] and glUniformMatrix4fv on the program in use.
  void uniform(const Call& c) {
    const std::string& n = c.name();
    if (m_program == 0) throw Error("a uniform set with no program in use");
    GlslProgram& p = program(m_program);
    const int64_t loc = num(c, 0);
    std::vector<float> v;
    if (n == "glUniformMatrix4fv") {
      if (num(c, 2) != 0) unsupported("a transposed matrix uniform");
      const Value& arr = c.arg(3);
      if (arr.kind != Value::Kind::array) throw Error("a matrix uniform without values");
      for (const Value& x : arr.items) v.push_back(float(x.number()));
    } else if (n.size() == 11 && n[9] >= '1' && n[9] <= '4' && (n[10] == 'f' || n[10] == 'i')) {
      for (int i = 0; i < n[9] - '0'; ++i) v.push_back(float(c.arg(size_t(1 + i)).number()));
    } else if (n.size() == 12 && n[9] >= '1' && n[9] <= '4' && (n[10] == 'f' || n[10] == 'i') && n[11] == 'v') {
      const Value& arr = c.arg(2);
      if (arr.kind != Value::Kind::array) throw Error("a uniform without values");
      for (const Value& x : arr.items) v.push_back(float(x.number()));
    } else if (n.rfind("glUniformMatrix", 0) == 0) {
      const auto it = p.uniform_names.find(loc);
      if (it != p.uniform_names.end()) p.uniforms.erase(it->second);  // not read by any recipe
      return;
    } else {
      unsupported("a call (" + n + ")");
    }
    if (loc < 0) return;  // a uniform the program does not use
    const auto it = p.uniform_names.find(loc);
    if (it == p.uniform_names.end()) throw Error("uniform location " + std::to_string(loc) + ", which was never asked for");
    p.uniforms[it->second] = std::move(v);
  }

  // Whether the texture on the unit of sampler `sampler` is a 256x1 ramp
  // mapping every level to itself (its red, green and blue texel i is i).
  bool identity_ramp(const GlslProgram& p, const std::string& sampler) const {
    const int64_t name = sampler_texture(p, sampler);
    if (name < 0) return false;
    const auto it = m_textures.find(uint32_t(name));
    if (it == m_textures.end() || !it->second.levels.count(0)) return false;
    const MipLevel& l = it->second.levels.at(0);
    if (l.width != 256 || l.height != 1) return false;
    for (int i = 0; i < 256; ++i)
      for (int ch = 0; ch < 3; ++ch)
        if (l.rgba[size_t(4 * i + ch)] != i) return false;
    return true;
  }

  // Whether the program has the uniform (glGetUniformLocation gave a
  // location: the compiler kept it).
  static bool located(const GlslProgram& p, const std::string& name) {
    for (const auto& [loc, uname] : p.uniform_names)
      if (uname == name) return true;
    return false;
  }

  const std::vector<float>* uniform_value(const GlslProgram& p, const std::string& name) const {
    const auto it = p.uniforms.find(name);
    return it == p.uniforms.end() ? nullptr : &it->second;
  }

  // A uniform's first `n` components: as set; 0 where the program has it
  // and it was never set (GLSL's initial value); `fallback` where the
  // compiler left it out (the permutation does not read it) or `name` is "".
  std::vector<float> uniform_or(const GlslProgram& p, const std::string& name, size_t n, float fallback) const {
    std::vector<float> v(n, fallback);
    if (name.empty()) return v;
    const std::vector<float>* u = uniform_value(p, name);
    if (!u && located(p, name)) std::fill(v.begin(), v.end(), 0.0f);
    if (u)
      for (size_t i = 0; i < n && i < u->size(); ++i) v[i] = (*u)[i];
    return v;
  }

  // The 2-D texture bound on the unit sampler `sampler` names (unit 0 when
  // never set, GLSL's initial value), or -1 for a unit beyond the 32 kept.
  int64_t sampler_texture(const GlslProgram& p, const std::string& sampler) const {
    const std::vector<float>* unit = uniform_value(p, sampler);
    const int u = unit && !unit->empty() ? int(unit->front()) : 0;
    return u < 0 || u >= int(m_unit_texture.size()) ? -1 : int64_t(m_unit_texture[size_t(u)]);
  }

  // Element `i` of an enabled attribute, from its buffer object or client
  // memory; false when it lies outside.
  bool fetch_attrib(const VertexAttrib& a, uint64_t i, float out[4]) const {
    if (a.buffer == 0) {
      if (!a.array.have_data || !fetch(a.array, i, out)) return false;
    } else {
      const auto it = m_buffers.find(a.buffer);
      if (it == m_buffers.end() || a.offset > it->second.size()) return false;
      if (!fetch(a.array, i, out, it->second.data() + a.offset, it->second.size() - a.offset)) return false;
    }
    if (a.normalized) {
      // OpenGL's conversion of normalised fixed-point data (since 4.2):
      // unsigned c / (2^b - 1), signed max(c / (2^(b-1) - 1), -1).
      float scale = 1;
      bool is_signed = false;
      switch (a.array.type) {
        case GL_UNSIGNED_BYTE: scale = 255.0f; break;
        case GL_BYTE: scale = 127.0f, is_signed = true; break;
        case GL_UNSIGNED_SHORT: scale = 65535.0f; break;
        case GL_SHORT: scale = 32767.0f, is_signed = true; break;
        case GL_UNSIGNED_INT: scale = 4294967295.0f; break;
        case GL_INT: scale = 2147483647.0f, is_signed = true; break;
        default: break;
      }
      for (int k = 0; k < a.array.size; ++k) out[k] = is_signed ? std::max(out[k] / scale, -1.0f) : out[k] / scale;
    }
    return true;
  }

  // The value of the attribute a recipe names, for vertex `i` (its
  // constant when disabled); false when none is bound to that name.
  bool attribute(const GlslProgram& p, const std::string& name, uint64_t i, float out[4]) const {
    const auto it = p.attributes.find(name);
    if (name.empty() || it == p.attributes.end()) return false;
    const VertexAttrib& a = m_attribs.at(size_t(it->second));
    if (!a.enabled) {
      std::copy(a.constant, a.constant + 4, out);
      return true;
    }
    if (!fetch_attrib(a, i, out)) throw Error("vertex " + std::to_string(i) + " lies outside the buffer of attribute " + name);
    return true;
  }

  // The indices of a draw through a program: from the element buffer
  // object (at the offset `indices` gives) or client memory.
  std::vector<uint32_t> program_indices(int64_t count, int64_t type, const Value& indices) const {
    if (m_element_buffer == 0) {
      if (indices.kind != Value::Kind::blob) throw Error("indices neither in a buffer object nor recorded");
      return read_indices(count, type, indices.bytes.data(), indices.bytes.size(), "a blob");
    }
    const auto it = m_buffers.find(m_element_buffer);
    const uint64_t offset = uint64_t(indices.integer());
    if (it == m_buffers.end() || offset > it->second.size()) throw Error("indices outside their buffer object");
    return read_indices(count, type, it->second.data() + offset, it->second.size() - offset, "what is left of a buffer");
  }

  // The projection and modelview of a draw from its one matrix uniform
  // (clip from object). An orthographic one (last row 0 0 0 1) is a 2-D
  // draw's projection. A perspective one is taken as P x MV, P a centred
  // perspective (a game's camera: x and y scales a and b, depth terms c and
  // d) and MV affine: then MV's third row is minus MVP's fourth, c and d
  // follow from MVP's third row. Where MV is a rotation and uniform scale
  // (the world, most models), a and b follow from the lengths of MVP's first
  // two rows against its fourth, and are kept as the view's; a model scaled
  // unevenly takes the view's a and b. MV = P^-1 x MVP.
  void split_mvp(const Mat4& mvp, Mat4& p, Mat4& mv) {
    if (mvp.at(3, 0) == 0 && mvp.at(3, 1) == 0 && mvp.at(3, 2) == 0 && mvp.at(3, 3) == 1) {
      p = mvp;
      mv = Mat4::identity();
      return;
    }
    const auto len3 = [&](int row) {
      return std::sqrt(double(mvp.at(row, 0)) * mvp.at(row, 0) + double(mvp.at(row, 1)) * mvp.at(row, 1) +
                       double(mvp.at(row, 2)) * mvp.at(row, 2));
    };
    const double w = len3(3);
    int k = 0;
    for (int i = 1; i < 3; ++i)
      if (std::abs(mvp.at(3, i)) > std::abs(mvp.at(3, k))) k = i;
    if (!(w > 0) || mvp.at(3, k) == 0) unsupported("a projection matrix uniform that is neither orthographic nor a perspective");
    const double c = -double(mvp.at(2, k)) / mvp.at(3, k);
    const double d = double(mvp.at(2, 3)) + c * mvp.at(3, 3);
    if (!(d != 0)) unsupported("a degenerate perspective matrix uniform");
    const auto factor = [&](double a, double b) {
      p = Mat4{};
      p.at(0, 0) = float(a);
      p.at(1, 1) = float(b);
      p.at(2, 2) = float(c);
      p.at(2, 3) = float(d);
      p.at(3, 2) = -1;
      p.at(3, 3) = 0;
      Mat4 inv{};
      inv.at(0, 0) = float(1 / a);
      inv.at(1, 1) = float(1 / b);
      inv.at(2, 2) = 0;
      inv.at(2, 3) = -1;
      inv.at(3, 2) = float(1 / d);
      inv.at(3, 3) = float(c / d);
      mv = inv * mvp;
    };
    // Whether MV's rows are orthogonal and of one length, within 1%
    // (DarkPlaces' matrices carry rounding of a few thousandths).
    const auto rigid = [&] {
      const auto dot3 = [&](int r1, int r2) {
        double sum = 0;
        for (int col = 0; col < 3; ++col) sum += double(mv.at(r1, col)) * mv.at(r2, col);
        return sum;
      };
      const double l0 = dot3(0, 0), l1 = dot3(1, 1), l2 = dot3(2, 2);
      const auto skew = [&](int r1, int r2, double a2, double b2) { return std::abs(dot3(r1, r2)) / std::sqrt(a2 * b2); };
      return l0 > 0 && l1 > 0 && l2 > 0 && std::abs(l0 / l2 - 1) < 0.02 && std::abs(l1 / l2 - 1) < 0.02 &&
             skew(0, 1, l0, l1) < 0.01 && skew(0, 2, l0, l2) < 0.01 && skew(1, 2, l1, l2) < 0.01;
    };
    const double a = len3(0) / w, b = len3(1) / w;
    if (a > 0 && b > 0) {
      factor(a, b);
      if (rigid()) {
        m_view_ab = {a, b};
        return;
      }
    }
    if (m_view_ab[0] > 0) {
      factor(m_view_ab[0], m_view_ab[1]);
      ++m_uneven_models;
      return;
    }
    unsupported("a perspective matrix uniform of an unevenly scaled model before any of the view's projection");
  }

  // A directionally lit model's light per vertex: ambient + diffuse x
  // max(0, N.L) (DarkPlaces' MODE_LIGHTDIRECTION with a flat normal map),
  // as the vertex colour scaled to at most 1 and that scale in the pass
  // colour (which keeps the program's alpha).
  // Returns the mean light over the vertices and channels.
  float light_vertices(const GlslProgram& pr, const ProgramRecipe& r, uint32_t lo, std::vector<ImmediateVertex>& v,
                       std::array<float, 4>& colour) const {
    const std::vector<float> ambient = uniform_or(pr, r.light_ambient, 3, 0), diffuse = uniform_or(pr, r.light_diffuse, 3, 0);
    const std::vector<float> dir = uniform_or(pr, r.light_dir, 3, 0);
    const Vec3 l = normalize(Vec3{dir[0], dir[1], dir[2]});
    std::vector<std::array<float, 3>> lit(v.size());
    float top = 1e-6f;
    double sum = 0;
    for (size_t i = 0; i < v.size(); ++i) {
      float k = 0;
      float n[4] = {0, 0, 0, 1};
      if (!r.light_dir.empty() && attribute(pr, r.normal, lo + i, n))
        k = std::max(0.0f, dot(normalize(Vec3{n[0], n[1], n[2]}), l));
      for (int ch = 0; ch < 3; ++ch) {
        lit[i][size_t(ch)] = std::max(0.0f, ambient[size_t(ch)] + diffuse[size_t(ch)] * k);
        top = std::max(top, lit[i][size_t(ch)]);
        sum += lit[i][size_t(ch)];
      }
    }
    for (size_t i = 0; i < v.size(); ++i) v[i].colour = pack_colour(lit[i][0] / top, lit[i][1] / top, lit[i][2] / top, 1.0f);
    colour[0] = colour[1] = colour[2] = top;
    return v.empty() ? 0.0f : float(sum / double(3 * v.size()));
  }

  // The uniforms ioquake3's vertex stages read, from the program in use.
  Ioq3Uniforms ioq3_uniforms(const GlslProgram& p) const {
    Ioq3Uniforms u;
    const auto get = [&](const char* name, float* out, size_t n, float fallback = 0) {
      const std::vector<float> v = uniform_or(p, name, n, fallback);
      std::copy(v.begin(), v.end(), out);
    };
    const auto vec3 = [&](const char* name, Vec3& out) {
      float f[3];
      get(name, f, 3);
      out = {f[0], f[1], f[2]};
    };
    get("u_BaseColor", u.base_colour.data(), 4);
    get("u_VertColor", u.vert_colour.data(), 4);
    get("u_DiffuseTexMatrix", u.tex_matrix.data(), 4);
    get("u_DiffuseTexOffTurb", u.off_turb.data(), 4);
    get("u_TCGen0", &u.tcgen, 1);
    vec3("u_TCGen0Vector0", u.tcgen_vector0);
    vec3("u_TCGen0Vector1", u.tcgen_vector1);
    vec3("u_LocalViewOrigin", u.local_view_origin);
    get("u_ColorGen", &u.colour_gen, 1);
    get("u_AlphaGen", &u.alpha_gen, 1);
    get("u_PortalRange", &u.portal_range, 1);
    vec3("u_AmbientLight", u.ambient_light);
    vec3("u_DirectedLight", u.directed_light);
    vec3("u_ModelLightDir", u.model_light_dir);
    get("u_DeformGen", &u.deform_gen, 1);
    get("u_DeformParams", u.deform_params.data(), 5);
    get("u_Time", &u.time, 1);
    get("u_FogDistance", u.fog_distance.data(), 4);
    get("u_FogDepth", u.fog_depth.data(), 4);
    get("u_FogEyeT", &u.fog_eye_t, 1);
    get("u_FogColorMask", u.fog_colour_mask.data(), 4);
    get("u_VertexLerp", &u.vertex_lerp, 1);
    if (const std::vector<float>* mm = uniform_value(p, "u_ModelMatrix"); mm && mm->size() == 16)
      for (int k = 0; k < 16; ++k) u.model_matrix.m[k / 4][k % 4] = (*mm)[size_t(k)];
    get("u_LightOrigin", u.light_origin.data(), 4);
    get("u_LightRadius", &u.light_radius, 1);
    get("u_DlightInfo", u.dlight_info.data(), 4);
    get("u_Color", u.colour.data(), 4);
    return u;
  }

  // An ioquake3 opengl2 draw's vertices: its vertex stage evaluated per
  // vertex (gl_programs.h, ioq3_vertex). The colour, which may exceed 1
  // (the map's overbright light), goes into the pass colour where every
  // vertex has the same, else into the vertex colours scaled to at most 1
  // with that scale in the pass colour. The fragment stage's alpha test
  // (u_AlphaTest) is the pass's.
  void ioq3_vertices(const GlslProgram& pr, const ProgramRecipe& r, uint32_t lo, std::vector<ImmediateVertex>& v,
                     MaterialKey& key) const {
    const Ioq3Uniforms u = ioq3_uniforms(pr);
    const Ioq3Stage& st = r.stage;
    std::vector<std::array<float, 4>> colour(v.size());
    bool same = true;
    float top = 1;
    for (size_t i = 0; i < v.size(); ++i) {
      Ioq3VertexIn in;
      float f[4] = {0, 0, 0, 1};
      const auto vec3 = [&](const char* name, Vec3& out) {
        f[0] = f[1] = f[2] = 0;
        f[3] = 1;
        if (attribute(pr, name, lo + i, f)) out = {f[0], f[1], f[2]};
      };
      vec3(r.position.c_str(), in.position);
      vec3("attr_Normal", in.normal);
      if (st.vertex_animation) {
        vec3("attr_Position2", in.position2);
        vec3("attr_Normal2", in.normal2);
      }
      float c[4] = {1, 1, 1, 1};
      if (!r.colour.empty() && attribute(pr, r.colour, lo + i, c)) in.colour = {c[0], c[1], c[2], c[3]};
      float t[4] = {0, 0, 0, 1};
      if (attribute(pr, r.uv, lo + i, t)) in.tex0 = {t[0], t[1]};
      float l[4] = {0, 0, 0, 1};
      if (attribute(pr, r.lightmap_uv, lo + i, l)) in.tex1 = {l[0], l[1]};
      const Ioq3VertexOut out = ioq3_vertex(st, u, in);
      v[i].position = {out.position.x, out.position.y, out.position.z, 1};
      v[i].uv[0] = {out.uv.x, out.uv.y};
      v[i].uv[1] = {out.lightmap.x, out.lightmap.y};
      colour[i] = out.colour;
      colour[i][3] = std::clamp(colour[i][3], 0.0f, 1.0f);
      for (int ch = 0; ch < 3; ++ch) {
        colour[i][size_t(ch)] = std::max(0.0f, colour[i][size_t(ch)]);
        top = std::max(top, colour[i][size_t(ch)]);
      }
      same = same && colour[i] == colour[0];
    }
    if (same && !v.empty()) {
      key.colour = colour[0];
      for (auto& x : v) x.colour = pack_colour(1, 1, 1, 1);
    } else {
      key.colour = {top, top, top, 1};
      for (size_t i = 0; i < v.size(); ++i)
        v[i].colour = pack_colour(colour[i][0] / top, colour[i][1] / top, colour[i][2] / top, colour[i][3]);
    }
    // u_AlphaTest: 1 discards alpha 0, 2 alpha >= 0.5, 3 alpha < 0.5.
    const float test = uniform_or(pr, "u_AlphaTest", 1, 0)[0];
    if (test == 1) {
      key.alpha_func = GL_GREATER;
      key.alpha_ref = 0;
    } else if (test == 2) {
      key.alpha_func = GL_LESS;
      key.alpha_ref = 0.5f;
    } else if (test == 3) {
      key.alpha_func = GL_GEQUAL;
      key.alpha_ref = 0.5f;
    } else if (test != 0) {
      unsupported("an ioquake3 alpha test " + std::to_string(test));
    }
  }

  // A draw through a GLSL program (its recipe: gl_programs.h).
  void program_draw(int64_t mode, const std::vector<uint32_t>& element) {
    const GlslProgram& pr = program(m_program);
    if (!pr.linked) throw Error("a draw with a program that was never linked");
    if (!pr.refusal.empty())
      unsupported("a draw through " + pr.refusal + " (docs/real-frames.md lists the game settings that leave them out)");
    refuse_common_state();
    const ProgramRecipe& r = pr.recipe;
    if (r.composite && m_fbo != 0) unsupported("a post-process into a framebuffer object");
    // Where it draws: the window, or a framebuffer object rendering the
    // view into a texture (composited into the window at the frame's end).
    if (m_fbo != 0) {
      const auto it = m_fbo_colour.find(m_fbo);
      if (it == m_fbo_colour.end() || it->second == 0)
        unsupported("a draw into a framebuffer object without a colour texture (a shadow map)");
      m_view_targets.insert(it->second);
    }
    MaterialKey key = state_key();
    std::vector<const ProgramRecipe::Layer*> tints;  // the recipe's layer of each key layer
    for (const auto& l : r.layers) {
      // A sampler the compiler left out is not sampled; one never set
      // samples unit 0 (GLSL's initial value).
      if (!located(pr, l.sampler)) continue;
      const int64_t bound = sampler_texture(pr, l.sampler);
      if (bound < 0) throw Error("sampler " + l.sampler + " on a unit beyond the 32 texture units kept");
      const auto name = uint32_t(bound);
      if (m_view_targets.count(name)) {
        // The view, rendered into a texture, drawn into the window whole:
        // the frame's draws already are that image.
        // (A generic copy: its one texture, untinted by vertex colours.)
        const bool copy = r.composite || (r.mode == "MODE_GENERIC" && r.layers.size() == 1 && r.colour.empty());
        if (m_fbo == 0 && copy && !m_blend) {
          for (const auto& id : r.identity_when) {
            const float x = uniform_or(pr, id.uniform, size_t(id.component) + 1, 0.0f)[size_t(id.component)];
            if (x != id.value) unsupported("a post-process that changes the view (" + id.uniform + " " + std::to_string(x) + ")");
          }
          if (!r.gamma_ramps.empty() && !identity_ramp(pr, r.gamma_ramps))
            unsupported("a post-process whose gamma ramps change the view");
          ++m_composites;
          return;
        }
        unsupported("a draw sampling the view it renders (post-processing)");
      }
      const int t = scene_texture(name);
      if (t == -3) unsupported("a draw sampling a depth texture (a shadow map)");
      if (t == -2) {
        ++m_incomplete;
        continue;
      }
      key.layers.push_back({t, l.coords, l.combine, 1.0f, LayerKind::diffuse});
      tints.push_back(&l);
    }
    // What else the program samples: fetched, not combined (their fetches
    // and traffic counted; gl_programs.h).
    // (ioquake3's fast-light programs sample nothing beyond their layers.)
    for (const auto& [sampler, kind] : darkplaces_2d_samplers()) {
      if (r.ioq3) break;
      if (!located(pr, sampler)) continue;
      bool drawn = false;
      for (const auto& l : r.layers) drawn = drawn || l.sampler == sampler;
      if (drawn) continue;
      const int64_t bound = sampler_texture(pr, sampler);
      const int t = bound < 0 ? -1 : scene_texture(uint32_t(bound));
      if (t >= 0) key.layers.push_back({t, TexCoords::surface, Combine::fetch, 1.0f, kind});
    }
    const std::vector<float> rgb = uniform_or(pr, r.colour_rgb, 3, 1), alpha = uniform_or(pr, r.alpha, 1, 1);
    key.colour = {rgb[0], rgb[1], rgb[2], alpha[0]};
    std::string approximation = r.approximation;
    const auto approximate = [&](const std::string& what) { approximation += (approximation.empty() ? "" : "; ") + what; };
    if (!r.ambient.empty() && !key.layers.empty()) {
      // diffuse x (ambient + light): the diffuse texture added again, times
      // the ambient (exact for a grey ambient on an opaque texture).
      // On a translucent texture the added layer would square its alpha
      // (oovr's added layers modulate alpha): the ambient is left out there.
      const std::vector<float> a = uniform_or(pr, r.ambient, 3, 0);
      if (a[0] != 0 || a[1] != 0 || a[2] != 0) {
        LayerKey again = key.layers.front();
        again.combine = Combine::add;
        again.scale = (a[0] + a[1] + a[2]) / 3;
        if (!m_scene.textures[size_t(again.texture)].opaque) {
          approximate("the ambient light left out on a translucent texture");
        } else {
          key.layers.push_back(again);
          if (a[0] != a[1] || a[1] != a[2]) approximate("a coloured ambient light added grey");
        }
      }
    }
    if (r.alpha_kill) {
      key.alpha_func = GL_GEQUAL;
      key.alpha_ref = 0.5f;
    }
    if (r.depth_only) {
      key.layers.clear();
      key.colour_write = false;
    }
    const std::vector<float>* mvp_value = uniform_value(pr, r.mvp);
    if (!mvp_value || mvp_value->size() != 16) throw Error("the program's " + r.mvp + " was never set");
    Mat4 mvp, tex = Mat4::identity();
    for (int k = 0; k < 16; ++k) mvp.m[k / 4][k % 4] = (*mvp_value)[size_t(k)];
    if (!r.tex_matrix.empty())
      if (const std::vector<float>* t = uniform_value(pr, r.tex_matrix); t && t->size() == 16)
        for (int k = 0; k < 16; ++k) tex.m[k / 4][k % 4] = (*t)[size_t(k)];
    const bool tex_identity = std::memcmp(&tex, &kIdentity, sizeof(Mat4)) == 0;
    // The vertices the draw uses.
    const uint32_t lo = *std::min_element(element.begin(), element.end());
    const uint32_t hi = *std::max_element(element.begin(), element.end());
    const uint64_t used = uint64_t(hi) - lo + 1;
    check_limit(used, InputLimits::get().elements, "elements", "a draw", "vertices");
    {
      const auto it = pr.attributes.find(r.position);
      if (it == pr.attributes.end() || !m_attribs.at(size_t(it->second)).enabled)
        unsupported("a draw whose positions (" + r.position + ") are not a vertex array");
      float f[4];
      if (!attribute(pr, r.position, hi, f)) unsupported("a draw without positions");
    }
    std::vector<ImmediateVertex> v(static_cast<size_t>(used));
    if (r.ioq3) ioq3_vertices(pr, r, lo, v, key);
    for (uint64_t i = 0; i < used && !r.ioq3; ++i) {
      float f[4] = {0, 0, 0, 1};
      attribute(pr, r.position, lo + i, f);
      v[i].position = {f[0], f[1], f[2], f[3]};
      float t[4] = {0, 0, 0, 1};
      if (attribute(pr, r.uv, lo + i, t)) {
        if (!tex_identity) {
          const Vec4 q = transform_point(tex, Vec3{t[0], t[1], 0});
          t[0] = q.x;
          t[1] = q.y;
        }
        v[i].uv[0] = {t[0], t[1]};
      }
      float l[4] = {0, 0, 0, 1};
      if (attribute(pr, r.lightmap_uv, lo + i, l)) v[i].uv[1] = {l[0], l[1]};
      float col[4] = {1, 1, 1, 1};
      attribute(pr, r.colour, lo + i, col);
      v[i].colour = pack_colour(col[0], col[1], col[2], col[3]);
    }
    float light = 1;  // the mean light of a lit draw, for the layers added before it
    if (!r.light_ambient.empty()) light = light_vertices(pr, r, lo, v, key.colour);
    for (size_t i = 0; i < tints.size(); ++i) {
      if (tints[i]->tint.empty()) continue;
      const std::vector<float> t = uniform_or(pr, tints[i]->tint, 3, 0);
      key.layers[i].scale = (t[0] + t[1] + t[2]) / 3 * (tints[i]->lit ? light : 1.0f);
      if (t[0] != t[1] || t[1] != t[2]) approximate(tints[i]->tint + " taken grey");
    }
    std::vector<uint32_t> local;
    triangles(mode, element.size(), local);
    for (uint32_t& x : local) x = element[x] - lo;
    if (!approximation.empty()) ++m_approximated[r.mode + ": " + approximation];
    Mat4 p, mv;
    split_mvp(mvp, p, mv);
    add_draw(v, local, key, p, mv);
  }

  std::unordered_map<uint32_t, std::string> m_buffers;  // buffer objects' bytes
  uint64_t m_buffer_bytes = 0;
  std::array<VertexAttrib, 16> m_attribs;  // the bound vertex array object's
  struct VertexArrayObject {
    std::array<VertexAttrib, 16> attribs;
    uint32_t element_buffer = 0;
  };
  // Every vertex array object but the bound one (whose state is m_attribs
  // and m_element_buffer); bounded, as a hostile capture could bind
  // millions.
  static constexpr size_t kMaxVertexArrays = 16384;
  std::unordered_map<uint32_t, VertexArrayObject> m_vaos;
  uint32_t m_vao = 0;
  std::unordered_map<uint32_t, std::vector<std::string>> m_shader_sources;
  std::unordered_map<uint32_t, GlslProgram> m_programs;
  uint32_t m_program = 0;
  uint32_t m_fbo = 0;                                   // the framebuffer object drawn into (0: the window)
  std::unordered_map<uint32_t, uint32_t> m_fbo_colour;  // each one's colour texture
  std::set<uint32_t> m_view_targets;                    // textures the view was rendered into
  bool m_separate_alpha = false;                        // glBlendFuncSeparate with other alpha factors
  uint64_t m_composites = 0;
  std::map<std::string, uint64_t> m_approximated;
  std::array<double, 2> m_view_ab{0, 0};  // the view's projection's x and y scales (split_mvp)
  uint64_t m_uneven_models = 0;           // draws whose colour a recipe approximates, by mode

  int select_unit(int64_t e, bool client) {
    const int64_t u = e - GL_TEXTURE0;
    if (u < 0 || u >= 32) throw Error("texture unit " + std::to_string(e));
    if (u >= kUnits) {
      // Units beyond the second are tracked as refused while selected.
      (client ? m_client_unit_high : m_unit_high) = true;
      return kUnits - 1;
    }
    (client ? m_client_unit_high : m_unit_high) = false;
    return int(u);
  }

  static Vec2 vec2_arg(const Call& c, size_t i) {
    const Value& v = c.arg(i);
    if (v.kind != Value::Kind::array || v.items.size() < 2) throw Error("a coordinate of fewer than 2 numbers");
    return {float(v.items[0].number()), float(v.items[1].number())};
  }

  void vertex(Vec4 p) {
    if (!m_in_begin) throw Error("a vertex outside glBegin/glEnd");
    if (m_immediate.size() >= (1u << 20)) throw Error("more than 2^20 vertices between glBegin and glEnd");
    m_immediate.push_back({p, {m_texcoord_now[0], m_texcoord_now[1]}, m_colour});
  }

  void tex_parameter(int64_t pname, double value) {
    GlTextureObject& t = m_textures[m_unit_texture[m_active_unit]];
    const int64_t v = int64_t(value);
    switch (pname) {
      case GL_TEXTURE_MIN_FILTER: t.min_filter = v; break;
      case GL_TEXTURE_MAG_FILTER: t.mag_filter = v; break;
      case GL_TEXTURE_WRAP_S: t.wrap_s = v; break;
      case GL_TEXTURE_WRAP_T: t.wrap_t = v; break;
      default: return;  // anisotropy, LOD bias and limits: see docs/real-frames.md
    }
    t.scene_index = -1;
  }

  // glTexImage2D(target, level, internalformat, width, height, border,
  // format, type, pixels) and glTexSubImage2D(target, level, xoffset,
  // yoffset, width, height, format, type, pixels).
  void tex_image(const Call& c, bool sub) {
    const int64_t target = num(c, 0);
    if (target >= GL_TEXTURE_CUBE_MAP_POSITIVE_X && target <= GL_TEXTURE_CUBE_MAP_POSITIVE_X + 5) return;  // see glBindTexture
    if (target != GL_TEXTURE_2D) unsupported("a texture target other than GL_TEXTURE_2D");
    ++m_stats.texture_uploads;
    const int level = int(num(c, 1));
    const int64_t width = num(c, sub ? 4 : 3), height = num(c, sub ? 5 : 4);
    const int64_t format = num(c, sub ? 6 : 6), type = num(c, sub ? 7 : 7);
    const Value& pixels = c.arg(8);
    if (level < 0 || level > 15) throw Error("mipmap level " + std::to_string(level));
    const InputLimits& lim = InputLimits::get();
    if (width < 0 || height < 0 || width > lim.image_side || height > lim.image_side)
      throw Error("a texture of " + std::to_string(width) + "x" + std::to_string(height) + " texels");
    if (!sub && num(c, 5) != 0) unsupported("a texture border");
    if (!sub && (format == GL_DEPTH_COMPONENT || format == GL_DEPTH_STENCIL) && c.arg(8).kind == Value::Kind::null) {
      // A depth texture a framebuffer object renders into (a shadow map):
      // no colour to sample; a draw that samples it is refused.
      GlTextureObject& t = m_textures[m_unit_texture[m_active_unit]];
      for (const auto& [lod, l] : t.levels) m_texel_bytes -= l.rgba.size();
      t.levels.clear();
      t.depth = true;
      t.scene_index = -1;
      return;
    }
    if (type != GL_UNSIGNED_BYTE) unsupported("texel type " + std::to_string(type) + " (only GL_UNSIGNED_BYTE)");
    int channels = 0;
    switch (format) {
      case GL_RGBA:
      case GL_BGRA: channels = 4; break;
      case GL_RGB:
      case GL_BGR: channels = 3; break;
      case GL_LUMINANCE_ALPHA: channels = 2; break;
      case GL_LUMINANCE:
      case GL_ALPHA:
      case GL_RED: channels = 1; break;
      default: unsupported("texel format " + std::to_string(format));
    }
    check_limit(uint64_t(width) * uint64_t(height), lim.image_texels, "image_texels", "a texture upload", "texels");
    GlTextureObject& t = m_textures[m_unit_texture[m_active_unit]];
    t.depth = false;
    // New contents from the game: no longer a copy of the view (glCopyTexSubImage2D).
    if (!sub) m_view_targets.erase(m_unit_texture[m_active_unit]);
    if (!sub) {
      t.base_format = base_format(num(c, 2));
      // Sized formats of fewer than 8 bits a channel (RGB4, RGB5, RGBA2,
      // RGBA4, RGB5_A1, R3_G3_B2): a driver may store fewer bits, oovr keeps 8.
      const int64_t f = num(c, 2);
      if (f == 0x804F || f == 0x8050 || f == 0x8055 || f == 0x8056 || f == 0x8057 || f == 0x2A10) ++m_low_bit_uploads;
      // Uncompressed texels with an S3TC internal format: the driver
      // compresses them (lossy, 4 or 8 bits a texel); oovr keeps them.
      if (f >= 0x83F0 && f <= 0x83F3) ++m_compressed_uploads;
    }
    MipLevel& dst = t.levels[level];
    int64_t x0 = 0, y0 = 0;
    if (sub) {
      x0 = num(c, 2);
      y0 = num(c, 3);
      if (x0 < 0 || y0 < 0 || x0 + width > dst.width || y0 + height > dst.height)
        throw Error("a sub-image outside level " + std::to_string(level) + " of texture " +
                    std::to_string(m_unit_texture[m_active_unit]));
    } else {
      // Every level of every texture counts against the scene's bytes.
      m_texel_bytes -= dst.rgba.size();
      m_texel_bytes += uint64_t(width) * uint64_t(height) * 4;
      check_limit(m_texel_bytes, lim.scene_bytes, "scene_bytes", "the capture's textures", "bytes");
      dst.width = int(width);
      dst.height = int(height);
      dst.rgba.assign(size_t(width * height * 4), 0);
    }
    t.scene_index = -1;
    if (pixels.kind == Value::Kind::null) return;  // allocated, contents undefined (zeros here)
    if (pixels.kind != Value::Kind::blob) unsupported("texels from a pixel unpack buffer");
    // Rows as the unpack state lays them out (glsize.hpp's _gl_image_size).
    const int64_t row_pixels = m_unpack_row_length > 0 ? m_unpack_row_length : width;
    const int64_t row_bytes = (row_pixels * channels + m_unpack_alignment - 1) / m_unpack_alignment * m_unpack_alignment;
    const int64_t first = m_unpack_skip_rows * row_bytes + m_unpack_skip_pixels * channels;
    const auto* src = reinterpret_cast<const uint8_t*>(pixels.bytes.data());
    if (height > 0 && width > 0 && uint64_t(first + (height - 1) * row_bytes + width * channels) > pixels.bytes.size())
      throw Error("texels of " + std::to_string(pixels.bytes.size()) + " bytes, fewer than a " + std::to_string(width) + "x" +
                  std::to_string(height) + " image needs");
    for (int64_t y = 0; y < height; ++y)
      for (int64_t x = 0; x < width; ++x) {
        const uint8_t* s = src + first + y * row_bytes + x * channels;
        uint8_t* d = dst.rgba.data() + ((y0 + y) * dst.width + (x0 + x)) * 4;
        uint8_t r = 0, g = 0, b = 0, a = 255;
        switch (format) {
          case GL_RGBA:
            r = s[0];
            g = s[1];
            b = s[2];
            a = s[3];
            break;
          case GL_BGRA:
            b = s[0];
            g = s[1];
            r = s[2];
            a = s[3];
            break;
          case GL_RGB:
            r = s[0];
            g = s[1];
            b = s[2];
            break;
          case GL_BGR:
            b = s[0];
            g = s[1];
            r = s[2];
            break;
          case GL_LUMINANCE_ALPHA:
            r = g = b = s[0];
            a = s[1];
            break;
          case GL_LUMINANCE: r = g = b = s[0]; break;
          case GL_ALPHA:
            r = g = b = 0;
            a = s[0];
            break;
          case GL_RED: r = s[0]; break;
        }
        d[0] = r;
        d[1] = g;
        d[2] = b;
        d[3] = a;
      }
  }

  // The base internal format (what the sampler returns) of an
  // internalformat argument: sized and unsized RGB, RGBA, luminance and
  // alpha formats, and the legacy component counts 1 to 4.
  static int64_t base_format(int64_t f) {
    switch (f) {
      case 3:
      case GL_RGB:
      case 0x804F:
      case 0x8050:
      case 0x8051:
      case 0x8052:
      case 0x8053:
      case 0x8054:
      case 0x2A10:
      case 0x83F0: return GL_RGB;  // COMPRESSED_RGB_S3TC_DXT1
      case 4:
      case GL_RGBA:
      case 0x8055:
      case 0x8056:
      case 0x8057:
      case 0x8058:
      case 0x8059:
      case 0x805A:
      case 0x83F1:  // COMPRESSED_RGBA_S3TC_DXT1, DXT3, DXT5
      case 0x83F2:
      case 0x83F3: return GL_RGBA;
      case 1:
      case GL_LUMINANCE:
      case 0x803F:
      case 0x8040:
      case 0x8041:
      case 0x8042: return GL_LUMINANCE;
      case 2:
      case GL_LUMINANCE_ALPHA:
      case 0x8043:
      case 0x8044:
      case 0x8045:
      case 0x8046:
      case 0x8047:
      case 0x8048: return GL_LUMINANCE_ALPHA;
      case GL_ALPHA:
      case 0x803B:
      case 0x803C:
      case 0x803D:
      case 0x803E: return GL_ALPHA;
      default: unsupported("texture internal format " + std::to_string(f));
    }
  }

  // The Scene texture of GL texture `name` now, made when it changed.
  int scene_texture(uint32_t name) {
    auto it = m_textures.find(name);
    if (it != m_textures.end() && it->second.depth) return -3;                 // a shadow map
    if (it == m_textures.end() || it->second.levels.count(0) == 0) return -2;  // incomplete: GL samples nothing
    GlTextureObject& t = it->second;
    if (t.scene_index >= 0) return t.scene_index;
    const MipLevel& base = t.levels.at(0);
    if (base.width == 0 || base.height == 0) return -2;
    const bool mip = t.min_filter != GL_NEAREST && t.min_filter != GL_LINEAR;
    Texture tex;
    tex.name = "gl texture " + std::to_string(name) + " v" + std::to_string(t.version++) + " (" + std::to_string(base.width) +
               "x" + std::to_string(base.height) + ")";
    tex.source = m_scene.name + "#" + tex.name;
    if (t.wrap_s != t.wrap_t) unsupported("different wrap modes in s and t");
    if (t.wrap_s == GL_CLAMP) ++m_clamp_notes;
    // oovr samples mipmapped textures trilinearly and others bilinearly.
    if ((t.min_filter != GL_LINEAR && t.min_filter != GL_LINEAR_MIPMAP_LINEAR) || t.mag_filter != GL_LINEAR) ++m_filter_notes;
    tex.wrap = t.wrap_s == GL_REPEAT ? Wrap::repeat : Wrap::clamp_to_edge;
    tex.mipmapped = mip;
    tex.levels.push_back(base);
    if (mip) {
      // The game's own levels, as uploaded, while they form a chain.
      for (int l = 1;; ++l) {
        const MipLevel& prev = tex.levels.back();
        if (prev.width == 1 && prev.height == 1) break;
        const auto lv = t.levels.find(l);
        const int w = std::max(1, prev.width / 2), h = std::max(1, prev.height / 2);
        if (lv == t.levels.end() || lv->second.width != w || lv->second.height != h) {
          if (!t.generated) ++m_mip_notes;
          tex.levels.resize(size_t(l));
          Texture rest;
          rest.levels.push_back(tex.levels.back());
          build_mip_chain(rest);
          tex.levels.insert(tex.levels.end(), rest.levels.begin() + 1, rest.levels.end());
          break;
        }
        tex.levels.push_back(lv->second);
      }
    }
    // What the sampler returns for the internal format (alpha 1 for RGB).
    for (MipLevel& l : tex.levels)
      for (size_t i = 0; i < l.rgba.size(); i += 4) {
        uint8_t* p = &l.rgba[i];
        switch (t.base_format) {
          case GL_RGB: p[3] = 255; break;
          case GL_LUMINANCE:
            p[1] = p[2] = p[0];
            p[3] = 255;
            break;
          case GL_LUMINANCE_ALPHA: p[1] = p[2] = p[0]; break;
          case GL_ALPHA: p[0] = p[1] = p[2] = 0; break;
          default: break;
        }
      }
    tex.opaque = true;
    for (size_t i = 3; i < tex.levels[0].rgba.size() && tex.opaque; i += 4) tex.opaque = tex.levels[0].rgba[i] == 255;
    m_scene.textures.push_back(std::move(tex));
    t.scene_index = int(m_scene.textures.size()) - 1;
    return t.scene_index;
  }

  // State refused at a fixed-function draw.
  void refuse_state() const {
    refuse_common_state();
    if (m_shade_model == GL_FLAT) unsupported("a draw with flat shading");
    if (m_draw_buffer != GL_BACK && m_draw_buffer != GL_BACK_LEFT) unsupported("a draw into a buffer other than the back buffer");
    if (m_array_buffer || m_element_buffer) unsupported("a fixed-function draw from buffer objects");
    if (m_unit_high || m_client_unit_high) unsupported("a draw with a texture unit beyond the second selected");
    if (std::memcmp(&m_texture_matrix.back(), &kIdentity, sizeof(Mat4)) != 0) unsupported("a draw with a texture matrix");
    if (m_fbo != 0) unsupported("a fixed-function draw into a framebuffer object");
  }

  // State refused at any draw, through a program or not.
  void refuse_common_state() const {
    for (const auto& [cap, what] : m_refused)
      if (!what.empty()) unsupported("a draw with " + what);
    if (m_polygon_mode != GL_FILL) unsupported("a draw with polygons drawn as lines or points (glPolygonMode)");
    if (m_blend && m_separate_alpha &&
        (m_src == GL_DST_ALPHA || m_src == GL_ONE_MINUS_DST_ALPHA || m_dst == GL_DST_ALPHA || m_dst == GL_ONE_MINUS_DST_ALPHA))
      unsupported("a blend by the destination's alpha, which another alpha blend function wrote");
    const auto& cm = m_colour_mask;
    if (!(cm[0] == cm[1] && cm[1] == cm[2] && cm[2] == cm[3])) unsupported("a draw with some colour channels masked");
    if (m_cull && m_cull_face == GL_FRONT_AND_BACK) unsupported("a draw with both faces culled");
    if (m_front_face != GL_CCW) unsupported("a draw with clockwise front faces (glFrontFace(GL_CW))");
  }

  static BlendFactor blend_factor(int64_t f) {
    switch (f) {
      case GL_ZERO: return BlendFactor::zero;
      case GL_ONE: return BlendFactor::one;
      case GL_SRC_COLOR: return BlendFactor::src_colour;
      case GL_ONE_MINUS_SRC_COLOR: return BlendFactor::one_minus_src_colour;
      case GL_SRC_ALPHA: return BlendFactor::src_alpha;
      case GL_ONE_MINUS_SRC_ALPHA: return BlendFactor::one_minus_src_alpha;
      case GL_DST_COLOR: return BlendFactor::dst_colour;
      case GL_ONE_MINUS_DST_COLOR: return BlendFactor::one_minus_dst_colour;
      case GL_DST_ALPHA: return BlendFactor::dst_alpha;
      case GL_ONE_MINUS_DST_ALPHA: return BlendFactor::one_minus_dst_alpha;
      default: unsupported("blend factor " + std::to_string(f));
    }
  }

  int material(const MaterialKey& k) {
    const auto it = m_materials.find(k);
    if (it != m_materials.end()) return it->second;
    Material m;
    m.name = "gl state " + std::to_string(m_materials.size());
    Pass p;
    for (const LayerKey& lk : k.layers) {
      TextureLayer l;
      l.kind = lk.combine == Combine::fetch ? lk.kind : p.layers.empty() ? LayerKind::diffuse : LayerKind::lightmap;
      l.texture = lk.texture;
      l.coords = lk.coords;
      l.scale = lk.scale;
      l.combine = lk.combine;
      if (lk.combine == Combine::add && p.layers.empty()) unsupported("GL_ADD on the first enabled texture unit");
      if (lk.combine == Combine::replace && !p.layers.empty()) unsupported("GL_REPLACE on the second texture unit");
      p.layers.push_back(l);
    }
    p.colour = {k.colour[0], k.colour[1], k.colour[2], k.colour[3]};
    p.src = blend_factor(k.src);
    p.dst = blend_factor(k.dst);
    switch (k.alpha_func) {
      case GL_ALWAYS: p.alpha_func = AlphaFunc::always; break;
      case GL_GREATER: p.alpha_func = AlphaFunc::greater; break;
      case GL_LESS: p.alpha_func = AlphaFunc::less; break;
      case GL_GEQUAL: p.alpha_func = AlphaFunc::gequal; break;
      default: unsupported("alpha function " + std::to_string(k.alpha_func));
    }
    p.alpha_ref = k.alpha_ref;
    switch (k.depth_func) {
      case GL_LESS: p.depth_func = DepthFunc::less; break;
      case GL_LEQUAL: p.depth_func = DepthFunc::lequal; break;
      case GL_EQUAL: p.depth_func = DepthFunc::equal; break;
      case GL_ALWAYS: p.depth_func = DepthFunc::always; break;
      default: unsupported("depth function " + std::to_string(k.depth_func));
    }
    p.depth_write = k.depth_write;
    p.colour_write = k.colour_write;
    p.offset_factor = k.offset_factor;
    p.offset_units = k.offset_units;
    m.two_sided = k.cull == 0;
    m.cull_front = k.cull == 2;
    m.passes.push_back(std::move(p));
    m_scene.materials.push_back(std::move(m));
    return m_materials[k] = int(m_scene.materials.size()) - 1;
  }

  // The fixed-function units' layers (at most two: kUnits).
  std::vector<LayerKey> unit_layers() {
    int texture[kUnits] = {-1, -1};
    for (int u = 0; u < kUnits; ++u) {
      if (!m_texture_2d[u]) continue;
      const int t = scene_texture(m_unit_texture[u]);
      if (t == -3) unsupported("a draw sampling a depth texture (a shadow map)");
      if (t == -2) {
        // An incomplete texture: OpenGL disables the unit's texturing.
        ++m_incomplete;
        continue;
      }
      texture[u] = t;
    }
    std::vector<LayerKey> layers;
    for (int u = 0; u < kUnits; ++u) {
      if (texture[u] < 0) continue;
      const bool first = layers.empty(), last = u == kUnits - 1 || texture[u + 1] < 0;
      const auto [env, scale] = resolve_env(u, first, last, m_scene.textures[size_t(texture[u])].opaque);
      LayerKey l;
      l.texture = texture[u];
      // Unit 1 alone is drawn as the first layer, from its own coordinates.
      l.coords = u == 0 ? TexCoords::surface : TexCoords::lightmap;
      l.scale = scale;
      switch (env) {
        case GL_MODULATE: l.combine = Combine::modulate; break;
        case GL_ADD: l.combine = Combine::add; break;
        case GL_REPLACE: l.combine = Combine::replace; break;
        default: unsupported("texture environment mode " + std::to_string(env));
      }
      layers.push_back(l);
    }
    if (texture[0] < 0 && texture[1] >= 0) m_unit1_alone = true;
    return layers;
  }

  // The fragment state of a draw (blending, tests, masks, culling, offset).
  MaterialKey state_key() {
    MaterialKey k;
    if (m_blend) {
      k.src = m_src;
      k.dst = m_dst;
    }
    if (m_alpha_test) {
      k.alpha_func = m_alpha_func;
      k.alpha_ref = m_alpha_ref;
    }
    if (m_depth_test) {
      k.depth_func = m_depth_func;
      k.depth_write = m_depth_mask;
    }
    k.colour_write = m_colour_mask[0];
    k.cull = m_cull ? (m_cull_face == GL_FRONT ? 2 : 1) : 0;
    if (m_offset) {
      k.offset_factor = m_offset_factor;
      k.offset_units = m_offset_units;
    }
    return k;
  }

  // Triangle list of a primitive of `count` vertices (GL's decompositions).
  static void triangles(int64_t mode, size_t count, std::vector<uint32_t>& out) {
    out.clear();
    const auto tri = [&](size_t a, size_t b, size_t c) {
      out.push_back(uint32_t(a));
      out.push_back(uint32_t(b));
      out.push_back(uint32_t(c));
    };
    switch (mode) {
      case GL_TRIANGLES:
        for (size_t i = 0; i + 2 < count; i += 3) tri(i, i + 1, i + 2);
        break;
      case GL_TRIANGLE_STRIP:
        for (size_t i = 0; i + 2 < count; ++i) i % 2 == 0 ? tri(i, i + 1, i + 2) : tri(i + 1, i, i + 2);
        break;
      case GL_TRIANGLE_FAN:
      case GL_POLYGON:
        for (size_t i = 1; i + 1 < count; ++i) tri(0, i, i + 1);
        break;
      case GL_QUADS:
        for (size_t i = 0; i + 3 < count; i += 4) {
          tri(i, i + 1, i + 2);
          tri(i, i + 2, i + 3);
        }
        break;
      case GL_QUAD_STRIP:
        for (size_t i = 0; i + 3 < count; i += 2) {
          tri(i, i + 1, i + 3);
          tri(i, i + 3, i + 2);
        }
        break;
      case GL_POINTS:
      case GL_LINES:
      case GL_LINE_LOOP:
      case GL_LINE_STRIP: unsupported("a draw of points or lines");
      default: throw Error("primitive mode " + std::to_string(mode));
    }
  }

  // Reads element `i` of a client array as `n` floats (missing ones as in
  // OpenGL: 0, 0, 0, 1); colours of unsigned bytes are normalised.
  // `base` and `size`: the bytes to read instead of the array's own (a
  // buffer object's, from the attribute's offset).
  static bool fetch(const ClientArray& a, uint64_t i, float out[4], const char* base = nullptr, size_t size = 0) {
    if (!base) {
      base = a.data.data();
      size = a.data.size();
    }
    int bytes = 0;
    switch (a.type) {
      case GL_FLOAT: bytes = 4; break;
      case GL_DOUBLE: bytes = 8; break;
      case GL_UNSIGNED_BYTE:
      case GL_BYTE: bytes = 1; break;
      case GL_SHORT:
      case GL_UNSIGNED_SHORT: bytes = 2; break;
      case GL_INT:
      case GL_UNSIGNED_INT: bytes = 4; break;
      default: unsupported("client array type " + std::to_string(a.type));
    }
    const uint64_t stride = a.stride ? uint64_t(a.stride) : uint64_t(bytes) * uint64_t(a.size);
    const uint64_t at = i * stride;
    if (i > (uint64_t(1) << 40) || at + uint64_t(bytes) * uint64_t(a.size) > size) return false;
    out[0] = out[1] = out[2] = 0;
    out[3] = 1;
    const char* p = base + at;
    for (int k = 0; k < a.size; ++k) {
      const char* q = p + k * bytes;
      switch (a.type) {
        case GL_FLOAT: out[k] = load<float>(q); break;
        case GL_DOUBLE: out[k] = float(load<double>(q)); break;
        case GL_UNSIGNED_BYTE: out[k] = float(load<uint8_t>(q)); break;
        case GL_BYTE: out[k] = float(load<int8_t>(q)); break;
        case GL_SHORT: out[k] = float(load<int16_t>(q)); break;
        case GL_UNSIGNED_SHORT: out[k] = float(load<uint16_t>(q)); break;
        case GL_INT: out[k] = float(load<int32_t>(q)); break;
        case GL_UNSIGNED_INT: out[k] = float(load<uint32_t>(q)); break;
      }
    }
    return true;
  }

  void indexed_draw(int64_t mode, int64_t count, int64_t type, const Value& indices) {
    if (count < 0) throw Error("a negative count");
    if (!in_window() || count == 0) return;
    if (indices.kind != Value::Kind::blob) unsupported("indices in a buffer object");
    array_vertices(mode, read_indices(count, type, indices.bytes.data(), indices.bytes.size(), "a blob"));
  }

  // The `count` indices of `type` at `base`, where `bytes` are left (in
  // `what`, for the error).
  static std::vector<uint32_t> read_indices(int64_t count, int64_t type, const char* base, uint64_t bytes, const char* what) {
    const int size = type == GL_UNSIGNED_INT ? 4 : type == GL_UNSIGNED_SHORT ? 2 : type == GL_UNSIGNED_BYTE ? 1 : 0;
    if (!size) throw Error("index type " + std::to_string(type));
    if (uint64_t(count) * uint64_t(size) > bytes)
      throw Error(std::to_string(count) + " indices in " + what + " of " + std::to_string(bytes) + " bytes");
    std::vector<uint32_t> element(static_cast<size_t>(count));
    for (int64_t i = 0; i < count; ++i) {
      const char* p = base + i * size;
      element[size_t(i)] = size == 4 ? load<uint32_t>(p) : size == 2 ? load<uint16_t>(p) : load<uint8_t>(p);
    }
    return element;
  }

  // Error unless vertex `i` lies in the vertex array apitrace recorded
  // (before anything the size of the draw is allocated).
  void check_vertex(uint64_t i) const {
    float f[4];
    if (!m_vertex.enabled) unsupported("a draw without a vertex array");
    if (!m_vertex.have_data || !fetch(m_vertex, i, f))
      throw Error("vertex " + std::to_string(i) + " lies outside the vertex array apitrace recorded");
  }

  // A draw from the client arrays: vertex `element[i]` of each array.
  void array_vertices(int64_t mode, const std::vector<uint32_t>& element) {
    if (!m_vertex.enabled) unsupported("a draw without a vertex array");
    refuse_state();
    const uint32_t lo = *std::min_element(element.begin(), element.end());
    const uint32_t hi = *std::max_element(element.begin(), element.end());
    check_vertex(hi);
    const uint64_t used = uint64_t(hi) - lo + 1;
    check_limit(used, InputLimits::get().elements, "elements", "a draw", "vertices");
    std::vector<ImmediateVertex> v(static_cast<size_t>(used));
    for (uint64_t i = 0; i < used; ++i) {
      float f[4];
      if (!m_vertex.have_data || !fetch(m_vertex, lo + i, f))
        throw Error("vertex " + std::to_string(lo + i) + " lies outside the vertex array apitrace recorded");
      v[i].position = {f[0], f[1], f[2], f[3]};
      for (int u = 0; u < kUnits; ++u) {
        v[i].uv[u] = m_texcoord_now[u];
        if (m_texcoord[u].enabled) {
          if (!m_texcoord[u].have_data || !fetch(m_texcoord[u], lo + i, f))
            throw Error("vertex " + std::to_string(lo + i) + " lies outside the texture coordinate array of unit " +
                        std::to_string(u));
          if (m_texcoord[u].size > 2 && f[3] != 1) unsupported("projective texture coordinates");
          v[i].uv[u] = {f[0], f[1]};
        }
      }
      v[i].colour = m_colour;
      if (m_colour_array.enabled) {
        if (!m_colour_array.have_data || !fetch(m_colour_array, lo + i, f))
          throw Error("vertex " + std::to_string(lo + i) + " lies outside the colour array");
        const float s = m_colour_array.type == GL_UNSIGNED_BYTE ? 1.0f / 255.0f : m_colour_array.type == GL_FLOAT ? 1.0f : 0;
        if (s == 0) unsupported("colours of type " + std::to_string(m_colour_array.type));
        v[i].colour = pack_colour(f[0] * s, f[1] * s, f[2] * s, m_colour_array.size == 4 ? f[3] * s : 1.0f);
      }
    }
    std::vector<uint32_t> local;
    triangles(mode, element.size(), local);
    for (uint32_t& x : local) x = element[x] - lo;
    add_draw(v, local);
  }

  void immediate_draw() {
    if (!in_window() || m_immediate.empty()) return;
    refuse_state();
    std::vector<uint32_t> local;
    triangles(m_begin_mode, m_immediate.size(), local);
    add_draw(m_immediate, local);
  }

  // Whether draws now go to the window or a framebuffer object with a
  // colour texture (not a shadow map's).
  bool draws_colour() const {
    if (m_fbo == 0) return true;
    const auto it = m_fbo_colour.find(m_fbo);
    return it != m_fbo_colour.end() && it->second != 0;
  }

  void clear(uint64_t mask) {
    if (!draws_colour()) return;  // a shadow map's clear: no draw of the view lands there
    if (mask & GL_STENCIL_BUFFER_BIT) {
      // The stencil buffer is not drawn with (the stencil test is refused).
    }
    if (!in_window() || !(mask & (GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT))) return;
    if (frame_draws().empty()) return;  // the frame starts cleared (to black, depth 1)
    if (mask & GL_COLOR_BUFFER_BIT) unsupported("a colour clear after the frame's first draw");
    // A depth clear of the scissor box (ioquake3 clears depth before each
    // 3-D model it draws into the HUD): a screen rectangle at the far plane
    // that writes depth only, drawn whatever is there.
    const int w = m_window_w, h = m_window_h;
    if (w <= 0 || h <= 0) throw Error("a clear before any glViewport");
    std::vector<ImmediateVertex> q(4);
    const float z = 1.0f;  // window depth 1: NDC z = 1
    q[0].position = {-1, -1, z, 1};
    q[1].position = {1, -1, z, 1};
    q[2].position = {1, 1, z, 1};
    q[3].position = {-1, 1, z, 1};
    for (auto& x : q) x.colour = 0xFFFFFFFFu;
    MaterialKey k;
    k.depth_func = GL_ALWAYS;
    k.depth_write = true;
    k.colour_write = false;
    Object o;
    o.name = kDepthClearName;
    o.mesh = mesh(q, {0, 1, 2, 0, 2, 3});
    o.material = material(k);
    o.view = DrawView::screen;
    o.clip_from_eye = Mat4::identity();
    o.world_from_object = Mat4::identity();
    o.scissor = m_scissor_test ? rect(m_scissor) : ViewRect{};
    push_draw(std::move(o));
    ++m_stats.clears;
  }

  // Appends a draw to the frame with the order it must keep (Object::after,
  // which OO-VR's middleware honours by keeping such draws in one batch,
  // Section 5.1): a draw of the same mesh as the one before is the next
  // stage of one surface (a Quake 3 shader's passes); a 2-D draw, a depth
  // clear and the draw after a depth clear follow the draw before them, so
  // the HUD is drawn over the world and a HUD model over its cleared box.
  void push_draw(Object o) {
    std::vector<Object>& list = frame_draws();
    if (!list.empty()) {
      const Object& prev = list.back();
      const bool clear = is_depth_clear(o), after_clear = is_depth_clear(prev);
      if (prev.mesh == o.mesh || o.view == DrawView::screen || clear || after_clear) o.after.push_back(uint32_t(list.size() - 1));
    }
    list.push_back(std::move(o));
  }

  std::vector<Object>& frame_draws() {
    const size_t f = size_t(m_frame - m_window.first);
    if (m_scene.frame_objects.size() <= f) m_scene.frame_objects.resize(f + 1);
    return m_scene.frame_objects[f];
  }

  ViewRect rect(const std::array<int, 4>& r) const {
    const float w = float(m_window_w), h = float(m_window_h);
    ViewRect v{float(r[0]) / w, float(r[1]) / h, float(r[0] + r[2]) / w, float(r[1] + r[3]) / h};
    v.x0 = std::clamp(v.x0, 0.0f, 1.0f);
    v.y0 = std::clamp(v.y0, 0.0f, 1.0f);
    v.x1 = std::clamp(v.x1, v.x0, 1.0f);
    v.y1 = std::clamp(v.y1, v.y0, 1.0f);
    return v;
  }

  int mesh(const std::vector<ImmediateVertex>& v, const std::vector<uint32_t>& indices) {
    Mesh m;
    m.vertices.resize(v.size());
    m.colours.resize(v.size());
    bool white = true;
    for (size_t i = 0; i < v.size(); ++i) {
      const Vec4& p = v[i].position;
      if (p.w != 1.0f) {
        if (p.w == 0.0f) unsupported("a vertex at infinity (w = 0)");
        m.vertices[i].position = {p.x / p.w, p.y / p.w, p.z / p.w};
      } else {
        m.vertices[i].position = {p.x, p.y, p.z};
      }
      m.vertices[i].uv = v[i].uv[0];
      m.vertices[i].lm_uv = v[i].uv[1];
      m.colours[i] = v[i].colour;
      white = white && v[i].colour == 0xFFFFFFFFu;
    }
    if (white) m.colours.clear();
    m.indices = indices;
    // The same vertices and indices drawn again (a wall in the next frame)
    // are the same mesh: the same memory, as the schemes and caches see it.
    uint64_t h = fnv(m.vertices.data(), m.vertices.size() * sizeof(Vertex));
    h = fnv(m.colours.data(), m.colours.size() * sizeof(uint32_t), h);
    h = fnv(m.indices.data(), m.indices.size() * sizeof(uint32_t), h);
    auto [it, fresh] = m_meshes.emplace(h, int(m_scene.meshes.size()));
    if (!fresh) {
      const Mesh& o = m_scene.meshes[size_t(it->second)];
      if (o.indices == m.indices && o.colours == m.colours && o.vertices.size() == m.vertices.size() &&
          std::memcmp(o.vertices.data(), m.vertices.data(), m.vertices.size() * sizeof(Vertex)) == 0)
        return it->second;
      // A hash collision: keep the new mesh apart.
    }
    m.name = "draw " + std::to_string(m_scene.meshes.size());
    m_scene.meshes.push_back(std::move(m));
    if (fresh) it->second = int(m_scene.meshes.size()) - 1;
    return int(m_scene.meshes.size()) - 1;
  }

  // A fixed-function draw: the units' layers and the fragment state, the
  // modelview and projection matrices.
  void add_draw(const std::vector<ImmediateVertex>& v, const std::vector<uint32_t>& indices) {
    MaterialKey key = state_key();
    key.layers = unit_layers();
    add_draw(v, indices, key, m_projection.back(), m_modelview.back());
  }

  // A draw: projected by p x modelview (vertices in object space).
  void add_draw(const std::vector<ImmediateVertex>& v, const std::vector<uint32_t>& indices, const MaterialKey& key,
                const Mat4& p, const Mat4& modelview) {
    ++m_stats.draws;
    if (m_window_w <= 0 || m_window_h <= 0) throw Error("a draw before any glViewport");
    Object o;
    o.mesh = mesh(v, indices);
    o.material = material(key);
    m_stats.triangles += indices.size() / 3;
    // Orthographic (a last row of 0 0 0 1): a 2-D draw, alike in both eyes.
    const bool ortho = p.at(3, 0) == 0 && p.at(3, 1) == 0 && p.at(3, 2) == 0 && p.at(3, 3) == 1;
    o.view = ortho ? DrawView::screen : DrawView::captured;
    if (ortho) ++m_stats.screen_draws;
    // The viewport and depth range folded into the projection: NDC of the
    // whole window, as the stereo rig's viewports expect.
    const float W = float(m_window_w), H = float(m_window_h);
    const float vx = float(m_viewport[0]), vy = float(m_viewport[1]), vw = float(m_viewport[2]), vh = float(m_viewport[3]);
    Mat4 fold;
    fold.at(0, 0) = vw / W;
    fold.at(0, 3) = (2 * vx + vw) / W - 1;
    fold.at(1, 1) = vh / H;
    fold.at(1, 3) = (2 * vy + vh) / H - 1;
    fold.at(2, 2) = m_depth_far - m_depth_near;
    fold.at(2, 3) = m_depth_far + m_depth_near - 1;
    // Identity folds (the whole window, depth range 0 to 1) leave the
    // game's matrices exact.
    o.clip_from_eye = std::memcmp(&fold, &kIdentity, sizeof(Mat4)) == 0 ? p : fold * p;
    o.world_from_object = modelview;
    ViewRect r = rect(m_viewport);
    if (m_scissor_test) {
      const ViewRect s = rect(m_scissor);
      r = {std::max(r.x0, s.x0), std::max(r.y0, s.y0), std::min(r.x1, s.x1), std::min(r.y1, s.y1)};
      r.x1 = std::max(r.x1, r.x0);
      r.y1 = std::max(r.y1, r.y0);
    }
    o.scissor = r;
    o.name = "frame " + std::to_string(m_frame) + " call " + std::to_string(m_call->no);
    push_draw(std::move(o));
  }

  void end_frame() {
    if (in_window()) frame_draws();  // a frame without draws still is one
    ++m_frame;
  }

  apitrace::Reader& m_reader;
  GlTraceWindow m_window;
  Scene m_scene;
  GlTraceStats m_stats;
  const Call* m_call = nullptr;
  int m_frame = 0;

  int64_t m_mode = GL_MODELVIEW;
  std::vector<Mat4> m_modelview{Mat4::identity()}, m_projection{Mat4::identity()}, m_texture_matrix{Mat4::identity()};
  std::array<int, 4> m_viewport{0, 0, 0, 0}, m_scissor{0, 0, 0, 0};
  int m_window_w = 0, m_window_h = 0;
  float m_depth_near = 0, m_depth_far = 1;
  bool m_blend = false, m_alpha_test = false, m_depth_test = false, m_cull = false, m_offset = false, m_scissor_test = false;
  int64_t m_src = GL_ONE, m_dst = GL_ZERO, m_alpha_func = GL_ALWAYS, m_depth_func = GL_LESS, m_cull_face = GL_BACK;
  int64_t m_front_face = GL_CCW, m_polygon_mode = GL_FILL, m_shade_model = GL_SMOOTH, m_draw_buffer = GL_BACK;
  float m_alpha_ref = 0, m_offset_factor = 0, m_offset_units = 0;
  bool m_depth_mask = true;
  std::array<bool, 4> m_colour_mask{true, true, true, true};
  std::map<int64_t, std::string> m_refused;           // state a draw is refused with, by capability
  uint32_t m_array_buffer = 0, m_element_buffer = 0;  // bound buffer objects
  bool m_unit_high = false, m_client_unit_high = false;

  int m_unit = 0, m_client_unit = 0;
  bool m_texture_2d[kUnits] = {false, false};
  int m_active_unit = 0;                      // glActiveTexture's unit (m_unit: the same, at most kUnits - 1)
  std::array<uint32_t, 32> m_unit_texture{};  // the 2-D texture bound on each unit
  TexEnv m_env[kUnits];
  std::unordered_map<uint32_t, GlTextureObject> m_textures;
  int m_unpack_alignment = 4, m_unpack_row_length = 0, m_unpack_skip_rows = 0, m_unpack_skip_pixels = 0;

  ClientArray m_vertex, m_colour_array, m_normal, m_texcoord[kUnits];
  uint32_t m_colour = 0xFFFFFFFFu;
  Vec2 m_texcoord_now[kUnits] = {{0, 0}, {0, 0}};
  bool m_in_begin = false;
  int64_t m_begin_mode = GL_TRIANGLES;
  std::vector<ImmediateVertex> m_immediate;

  std::map<MaterialKey, int> m_materials;
  std::unordered_map<uint64_t, int> m_meshes;
  int m_clamp_notes = 0, m_mip_notes = 0, m_incomplete = 0, m_filter_notes = 0;
  uint64_t m_texel_bytes = 0;  // of every level uploaded
  int m_low_bit_uploads = 0, m_compressed_uploads = 0;
  bool m_unit1_alone = false;
};

}  // namespace

GameDraws game_draws(const Scene& scene, int frame) {
  GameDraws g;
  for (const Object& o : scene.draws(frame)) {
    if (is_depth_clear(o)) {
      ++g.clears;
      continue;
    }
    ++g.draws;
    g.triangles += scene.meshes[size_t(o.mesh)].triangle_count();
    g.screen += o.view == DrawView::screen;
  }
  return g;
}

Scene import_gl_trace(const std::string& path, const GlTraceWindow& window, GlTraceStats* stats) {
  apitrace::Reader reader(path);
  return Interpreter(reader, window).run(stats);
}

Scene import_gl_trace_bytes(std::string bytes, const std::string& name, const GlTraceWindow& window, GlTraceStats* stats) {
  apitrace::Reader reader(std::move(bytes), name);
  return Interpreter(reader, window).run(stats);
}

}  // namespace oovr
