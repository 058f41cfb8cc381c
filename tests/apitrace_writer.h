// Writes apitrace trace files (docs/apitrace-format.md) for tests and fuzz
// seeds: a trace of chosen calls without a game or apitrace. Each value is
// encoded to bytes by a member function and a call is a name with named,
// encoded arguments:
//
//   TraceWriter w;
//   w.call("glDrawArrays", {{"mode", w.e("GL_TRIANGLES", 4)}, {"first", w.u(0)}, {"count", w.u(3)}});
//   std::string file = w.finish();
#pragma once

#include <snappy.h>

#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace oovr::test {

class TraceWriter {
 public:
  using Arg = std::pair<std::string, std::string>;  // name, encoded value

  // `properties` follow the version (version 6 only).
  explicit TraceWriter(unsigned version = 6,
                       std::vector<std::pair<std::string, std::string>> properties = {{"process.name", "test"}})
      : m_version(version) {
    put_uint(m_stream, version);
    if (version >= 6) {
      put_uint(m_stream, version);
      for (const auto& [k, v] : properties) {
        put_string(m_stream, k);
        put_string(m_stream, v);
      }
      put_uint(m_stream, 0);
    }
  }

  // Encoded values.
  static std::string null() { return std::string(1, '\x00'); }
  static std::string boolean(bool b) { return std::string(1, b ? '\x02' : '\x01'); }
  static std::string u(uint64_t v) { return tagged(0x04, v); }
  static std::string i(int64_t v) { return v < 0 ? tagged(0x03, uint64_t(-v)) : tagged(0x04, uint64_t(v)); }
  static std::string f(float v) {
    std::string s(1, '\x05');
    s.append(reinterpret_cast<const char*>(&v), 4);
    return s;
  }
  static std::string d(double v) {
    std::string s(1, '\x06');
    s.append(reinterpret_cast<const char*>(&v), 8);
    return s;
  }
  static std::string str(const std::string& v) {
    std::string s(1, '\x07');
    put_string(s, v);
    return s;
  }
  static std::string blob(const void* data, size_t n) {
    std::string s(1, '\x08');
    put_uint(s, n);
    s.append(static_cast<const char*>(data), n);
    return s;
  }
  template <class T>
  static std::string blob(const std::vector<T>& v) {
    return blob(v.data(), v.size() * sizeof(T));
  }
  static std::string opaque(uint64_t address) { return tagged(0x0d, address); }
  static std::string array(const std::vector<std::string>& items) {
    std::string s(1, '\x0b');
    put_uint(s, items.size());
    for (const auto& i : items) s += i;
    return s;
  }
  // An enum value; each name gets a signature of its own, written on first use.
  std::string e(const std::string& name, int64_t value) {
    std::string s(1, '\x09');
    const auto key = name + "=" + std::to_string(value);
    auto it = m_enums.find(key);
    if (it != m_enums.end()) {
      put_uint(s, it->second);
    } else {
      const uint64_t id = m_enums.size();
      m_enums[key] = id;
      put_uint(s, id);
      if (m_version >= 3) put_uint(s, 1);
      put_string(s, name);
      s += i(value);
    }
    if (m_version >= 3) s += i(value);
    return s;
  }

  // One call: its ENTER (with the arguments) and its LEAVE (with `ret` when
  // not empty). Returns its number.
  uint64_t call(const std::string& name, const std::vector<Arg>& args, const std::string& ret = "", bool fake = false) {
    const uint64_t no = enter(name, args, fake);
    leave(no, ret);
    return no;
  }
  uint64_t enter(const std::string& name, const std::vector<Arg>& args, bool fake = false, uint64_t thread = 0) {
    m_stream += '\x00';
    if (m_version >= 4) put_uint(m_stream, thread);
    auto it = m_functions.find(name);
    if (it != m_functions.end()) {
      put_uint(m_stream, it->second);
    } else {
      const uint64_t id = m_functions.size() + 4;  // apitrace's API functions start at 4
      m_functions[name] = id;
      put_uint(m_stream, id);
      put_string(m_stream, name);
      put_uint(m_stream, args.size());
      for (const auto& a : args) put_string(m_stream, a.first);
    }
    if (fake) {
      m_stream += '\x05';
      put_uint(m_stream, 1);
    }
    for (size_t k = 0; k < args.size(); ++k) {
      m_stream += '\x01';
      put_uint(m_stream, k);
      m_stream += args[k].second;
    }
    m_stream += '\x00';
    return m_calls++;
  }
  void leave(uint64_t no, const std::string& ret = "") {
    m_stream += '\x01';
    put_uint(m_stream, no);
    if (!ret.empty()) {
      m_stream += '\x02';
      m_stream += ret;
    }
    m_stream += '\x00';
  }
  // OpenGL calls a game makes, as apitrace records them: the window's
  // viewport, and a 2x2 RGBA texture (16 bytes of texels) bound and uploaded.
  void gl_viewport(int width, int height) {
    call("glViewport", {{"x", i(0)}, {"y", i(0)}, {"width", i(width)}, {"height", i(height)}});
  }
  void gl_texture_2x2(uint64_t name, const std::vector<uint8_t>& rgba) {
    call("glBindTexture", {{"target", e("GL_TEXTURE_2D", 0x0DE1)}, {"texture", u(name)}});
    call("glTexImage2D", {{"target", e("GL_TEXTURE_2D", 0x0DE1)},
                          {"level", i(0)},
                          {"internalformat", e("GL_RGBA", 0x1908)},
                          {"width", i(2)},
                          {"height", i(2)},
                          {"border", i(0)},
                          {"format", e("GL_RGBA", 0x1908)},
                          {"type", e("GL_UNSIGNED_BYTE", 0x1401)},
                          {"pixels", blob(rgba)}});
  }

  // A client array as apitrace records it before a draw: a fake
  // glVertexPointer, glTexCoordPointer or glColorPointer call whose pointer
  // is the array's bytes (tightly packed).
  template <class T>
  void gl_client_array(const std::string& function, int size, const std::string& type, int64_t type_value,
                       const std::vector<T>& data) {
    call(function, {{"size", i(size)}, {"type", e(type, type_value)}, {"stride", i(0)}, {"pointer", blob(data)}}, "", true);
  }

  // An OpenGL 3 game in DarkPlaces' manner (gl_programs.h): program `id`
  // of one permutation (each define in its own source string, the shader's
  // body last), its attributes bound by name, the locations of its matrix,
  // samplers and colours asked for (0 to 4) and the program used.
  uint64_t gl_program(uint64_t id, const std::vector<std::string>& defines) {
    std::vector<std::string> strings = {str("#version 140\n")};
    for (const auto& d : defines) strings.push_back(str("#define " + d + "\n"));
    strings.push_back(str("#define NOT_A_PERMUTATION\nvoid main() {}\n"));  // the body: its #defines are not permutations
    return gl_link_program(id, e("GL_FRAGMENT_SHADER", 0x8B30), strings, {"Attrib_Position", "Attrib_Color", "Attrib_TexCoord0"},
                           {"ModelViewProjectionMatrix", "Texture_First", "Texture_Color", "Color_Diffuse", "Alpha"});
  }
  // Program `id` of one shader (number id + 100, of type `type`) from
  // `strings`: the attributes bound to locations 0, 1, ... in order, linked,
  // used, and the uniforms' locations asked for (0, 1, ... in order).
  uint64_t gl_link_program(uint64_t id, const std::string& type, const std::vector<std::string>& strings,
                           const std::vector<std::string>& attributes, const std::vector<std::string>& uniforms) {
    const uint64_t shader = id + 100;
    call("glCreateShader", {{"type", type}}, u(shader));
    call("glShaderSource",
         {{"shader", u(shader)}, {"count", i(int64_t(strings.size()))}, {"string", array(strings)}, {"length", null()}});
    call("glCreateProgram", {}, u(id));
    call("glAttachShader", {{"program", u(id)}, {"shader", u(shader)}});
    for (size_t k = 0; k < attributes.size(); ++k)
      call("glBindAttribLocation", {{"program", u(id)}, {"index", u(uint64_t(k))}, {"name", str(attributes[k])}});
    call("glLinkProgram", {{"program", u(id)}});
    call("glUseProgram", {{"program", u(id)}});
    for (size_t k = 0; k < uniforms.size(); ++k)
      call("glGetUniformLocation", {{"program", u(id)}, {"name", str(uniforms[k])}}, i(int64_t(k)));
    return id;
  }

  // A program in ioquake3's opengl2 manner (gl_programs.h): one source
  // string, a header of the constants' and the permutation's #defines
  // closed by `#line 0`, then a body declaring what the `shader` (generic,
  // lightall, dlight) declares. Attributes bound: attr_Position 0,
  // attr_Color 1, attr_TexCoord0 2, attr_TexCoord1 3, attr_Normal 4,
  // attr_Position2 5, attr_Normal2 6; uniform locations:
  // u_ModelViewProjectionMatrix 0, u_DiffuseMap 1, u_LightMap 2,
  // u_BaseColor 3, u_VertColor 4, u_AlphaTest 5, u_VertexLerp 6. The
  // program is used.
  uint64_t gl_ioq3_program(uint64_t id, const std::string& shader, const std::vector<std::string>& defines) {
    std::string header =
        "#version 150\n#define attribute in\n#define varying out\n#ifndef M_PI\n#define M_PI 3.14159265358979323846\n#endif\n";
    for (const char* c :
         {"DGEN_WAVE_SIN 1", "DGEN_WAVE_SQUARE 2", "DGEN_WAVE_TRIANGLE 3", "DGEN_WAVE_SAWTOOTH 4", "DGEN_WAVE_INVERSE_SAWTOOTH 5",
          "DGEN_BULGE 7", "DGEN_MOVE 8", "TCGEN_LIGHTMAP 2", "TCGEN_TEXTURE 3", "TCGEN_ENVIRONMENT_MAPPED 4", "TCGEN_FOG 5",
          "TCGEN_VECTOR 6", "CGEN_LIGHTING_DIFFUSE 11", "AGEN_LIGHTING_SPECULAR 6", "AGEN_PORTAL 8"})
      header += std::string("#define ") + c + "\n";
    for (const auto& d : defines) header += "#define " + d + "\n";
    std::string body = "attribute vec3 attr_Position;\n";
    if (shader == "generic") body += "uniform vec4   u_BaseColor;\nvarying vec2   var_DiffuseTex;\n";
    else if (shader == "lightall") body += "uniform vec4   u_BaseColor;\nvarying vec4   var_TexCoords;\n";
    else if (shader == "dlight") body += "uniform vec4   u_DlightInfo;\nvarying vec2   var_Tex1;\n";
    body += "void main() {}\n";
    return gl_link_program(
        id, e("GL_VERTEX_SHADER", 0x8B31), {str(header + "#line 0\n" + body)},
        {"attr_Position", "attr_Color", "attr_TexCoord0", "attr_TexCoord1", "attr_Normal", "attr_Position2", "attr_Normal2"},
        {"u_ModelViewProjectionMatrix", "u_DiffuseMap", "u_LightMap", "u_BaseColor", "u_VertColor", "u_AlphaTest",
         "u_VertexLerp"});
  }

  void gl_uniform4f(int64_t location, float x, float y, float z, float w) {
    call("glUniform4f", {{"location", i(location)}, {"v0", f(x)}, {"v1", f(y)}, {"v2", f(z)}, {"v3", f(w)}});
  }
  void gl_uniform_matrix(const std::vector<float>& m) {
    std::vector<std::string> items;
    for (float x : m) items.push_back(f(x));
    call("glUniformMatrix4fv", {{"location", i(0)}, {"count", i(1)}, {"transpose", e("GL_FALSE", 0)}, {"value", array(items)}});
  }
  // A quad at depth z (in a vertex buffer), drawn through the program in use.
  void gl_buffer_quad(float z) {
    const std::vector<float> xyz = {-1, -1, z, 1, -1, z, 1, 1, z, -1, 1, z};
    const std::vector<float> st = {0, 0, 1, 0, 1, 1, 0, 1};
    const std::vector<uint16_t> idx = {0, 1, 2, 0, 2, 3};
    call("glBindBuffer", {{"target", e("GL_ARRAY_BUFFER", 0x8892)}, {"buffer", u(1)}});
    call("glBufferData",
         {{"target", e("GL_ARRAY_BUFFER", 0x8892)}, {"size", i(4096)}, {"data", null()}, {"usage", e("GL_STREAM_DRAW", 0x88E0)}});
    call("glBufferSubData", {{"target", e("GL_ARRAY_BUFFER", 0x8892)}, {"offset", i(64)}, {"size", i(48)}, {"data", blob(xyz)}});
    call("glBufferSubData", {{"target", e("GL_ARRAY_BUFFER", 0x8892)}, {"offset", i(112)}, {"size", i(32)}, {"data", blob(st)}});
    call("glEnableVertexAttribArray", {{"index", u(0)}});
    call("glVertexAttribPointer", {{"index", u(0)},
                                   {"size", i(3)},
                                   {"type", e("GL_FLOAT", 0x1406)},
                                   {"normalized", e("GL_FALSE", 0)},
                                   {"stride", i(12)},
                                   {"pointer", u(64)}});
    call("glEnableVertexAttribArray", {{"index", u(2)}});
    call("glVertexAttribPointer", {{"index", u(2)},
                                   {"size", i(2)},
                                   {"type", e("GL_FLOAT", 0x1406)},
                                   {"normalized", e("GL_FALSE", 0)},
                                   {"stride", i(8)},
                                   {"pointer", u(112)}});
    call("glVertexAttrib4f", {{"index", u(1)}, {"x", f(1)}, {"y", f(0.5f)}, {"z", f(1)}, {"w", f(1)}});
    call("glBindBuffer", {{"target", e("GL_ELEMENT_ARRAY_BUFFER", 0x8893)}, {"buffer", u(2)}});
    call("glBufferData", {{"target", e("GL_ELEMENT_ARRAY_BUFFER", 0x8893)},
                          {"size", i(1024)},
                          {"data", null()},
                          {"usage", e("GL_STREAM_DRAW", 0x88E0)}});
    call("glBufferSubData",
         {{"target", e("GL_ELEMENT_ARRAY_BUFFER", 0x8893)}, {"offset", i(32)}, {"size", i(12)}, {"data", blob(idx)}});
    call("glDrawElements",
         {{"mode", e("GL_TRIANGLES", 4)}, {"count", i(6)}, {"type", e("GL_UNSIGNED_SHORT", 0x1403)}, {"indices", u(32)}});
  }

  // Raw bytes appended to the stream (malformed events).
  void raw(const std::string& bytes) { m_stream += bytes; }
  const std::string& stream() const { return m_stream; }

  // The file: 'a' 't' and the stream in snappy chunks of `chunk` bytes.
  std::string finish(size_t chunk = 1 << 20) const { return container(m_stream, chunk); }
  static std::string container(const std::string& stream, size_t chunk = 1 << 20) {
    std::string out = "at";
    for (size_t at = 0; at < stream.size(); at += chunk) {
      std::string c;
      snappy::Compress(stream.data() + at, std::min(chunk, stream.size() - at), &c);
      const uint32_t n = uint32_t(c.size());
      const char len[4] = {char(n), char(n >> 8), char(n >> 16), char(n >> 24)};
      out.append(len, 4);
      out += c;
    }
    return out;
  }

  static void put_uint(std::string& s, uint64_t v) {
    do {
      uint8_t b = v & 0x7F;
      v >>= 7;
      if (v) b |= 0x80;
      s += char(b);
    } while (v);
  }
  static void put_string(std::string& s, const std::string& v) {
    put_uint(s, v.size());
    s += v;
  }

 private:
  static std::string tagged(char tag, uint64_t v) {
    std::string s(1, tag);
    put_uint(s, v);
    return s;
  }

  unsigned m_version;
  std::string m_stream;
  std::map<std::string, uint64_t> m_functions;
  std::map<std::string, uint64_t> m_enums;
  uint64_t m_calls = 0;
};

}  // namespace oovr::test
