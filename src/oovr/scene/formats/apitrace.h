// A reader of apitrace's trace files (the format apitrace 11 writes; see
// docs/apitrace-format.md): the snappy container, the version 0-6 event
// stream, signatures defined on first use, values, and frames ended by the
// swap calls. oovr's own code: apitrace's parser checks almost none of the
// sizes a file declares, so every length, count, id, nesting depth and
// chunk is bounded here and a bad file is an Error naming the file, the
// byte offset and what is wrong (docs/reliability.md).
//
// Calls are read one at a time, in the order their LEAVE events arrive (as
// `apitrace dump` prints them), so a trace of gigabytes is read in bounded
// memory. Blobs of calls the caller does not want can be skipped without
// being copied (read_blobs = false).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace oovr::apitrace {

// A call's flags: those kept in the file (fake) and those apitrace derives
// from the function's name (trace_parser_flags.cpp); `end_frame` marks the
// call that ends a frame (glXSwapBuffers, eglSwapBuffers, ...).
enum CallFlags : uint32_t { kFake = 1u << 0, kEndFrame = 1u << 5, kIncomplete = 1u << 6 };

struct EnumSig {
  std::vector<std::pair<std::string, int64_t>> values;
  // The name of `value` in this enum, or nullptr.
  const std::string* name_of(int64_t value) const;
};

struct FunctionSig {
  uint64_t id = 0;
  std::string name;
  std::vector<std::string> arg_names;
  uint32_t flags = 0;  // kEndFrame where the name ends a frame
};

struct Value {
  enum class Kind : uint8_t {
    null,
    boolean,
    sint,
    uint,
    real,
    string,
    blob,
    enumeration,
    bitmask,
    array,
    structure,
    opaque,
    wstring
  };
  Kind kind = Kind::null;
  bool skipped = false;                // a blob whose bytes were not read (read_blobs = false)
  int64_t i = 0;                       // sint, enumeration, boolean (0/1)
  uint64_t u = 0;                      // uint, bitmask, opaque (an address), blob and string byte counts when skipped
  double d = 0;                        // real (FLOAT and DOUBLE)
  std::string bytes;                   // string, blob (raw bytes), wstring (as UTF-8)
  std::vector<Value> items;            // array elements, structure members
  std::shared_ptr<const EnumSig> sig;  // enumeration (shared: a value outlives its reader)

  bool is_number() const {
    return kind == Kind::sint || kind == Kind::uint || kind == Kind::real || kind == Kind::boolean || kind == Kind::enumeration ||
           kind == Kind::bitmask;
  }
  // The value as a number: integers and enums exactly, reals as they are;
  // null is 0 (apitrace writes a null pointer and an opaque 0 alike).
  double number() const;
  int64_t integer() const;
};

struct Call {
  uint64_t no = 0;  // call number: the order of ENTER events, from 0
  uint32_t thread = 0;
  std::shared_ptr<const FunctionSig> sig;  // shared: a call outlives its reader
  std::vector<Value> args;                 // by argument index; missing ones are null
  Value ret;
  uint32_t flags = 0;

  const std::string& name() const { return sig->name; }
  bool fake() const { return flags & kFake; }
  bool ends_frame() const { return flags & kEndFrame; }
  // Argument `index`; Error naming the call when it is missing.
  const Value& arg(size_t index) const;
};

// Bounds beyond which a file is refused, each far above what apitrace
// writes for a game: the GLenum signature lists about 4,000 names, a game's
// largest blob is a texture upload or a client array of a few megabytes.
struct ReaderLimits {
  uint64_t string_bytes = 1 << 20;            // names and string values (a GLSL program's source: 75 KB in DarkPlaces)
  uint64_t blob_bytes = uint64_t(256) << 20;  // blobs of one call (client arrays, indices, texels)
  uint64_t count = 1 << 16;                   // arguments, members, enum entries, array elements, backtrace frames
  uint64_t signature_id = 1 << 20;            // ids of functions, enums, structs, bitmasks, frames
  uint64_t call_values = 1 << 20;             // values in one call's event (array elements included)
  int depth = 64;                             // nesting of arrays and structures
  uint64_t open_calls = 1 << 10;              // calls entered and not yet left (threads interleaving)
};

class Reader {
 public:
  // Opens `path`: Error when it cannot be read or is not a snappy
  // container (gzip, Brotli and zstd ones are named and refused).
  explicit Reader(const std::string& path, ReaderLimits limits = {});
  // Reads from bytes held in memory (tests and the fuzz target).
  Reader(std::string bytes, const std::string& name, ReaderLimits limits = {});
  ~Reader();
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  // The stream's version and semantic version, and its properties
  // (process.name).
  unsigned version() const;
  unsigned semantic_version() const;
  const std::vector<std::pair<std::string, std::string>>& properties() const;

  // Whether next() copies blob bytes; when false a blob is a Value with
  // skipped = true and u = its size. May be changed between calls.
  void read_blobs(bool on);
  // Whether next() copies the blobs of each call, decided by its function
  // (replaces read_blobs until cleared with an empty function): a reader
  // that needs the texels of texture uploads but not the client arrays of
  // draws it skips reads faster.
  void read_blobs_of(std::function<bool(const FunctionSig&)> wanted);
  // The next completed call, or false at the end of the trace (calls still
  // open then are returned first, flagged kIncomplete). Throws Error naming
  // the file and offset on malformed data.
  bool next(Call& call);
  // Whether the file ends inside a chunk or a call (a traced game that was
  // killed): the calls before that point are read, the cut one is dropped.
  bool truncated() const;
  // Bytes of the file read so far: the end of the chunk the last call came
  // from. The file up to there is itself a trace (cut_trace).
  uint64_t chunk_end() const;
  // Bytes of the logical (decompressed) stream read so far, and of the file.
  uint64_t offset() const;
  const std::string& name() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> m;
};

// Writes to `out` the part of the trace at `in` that holds its frames 0 to
// `last_frame`: its chunks up to the one that ends that frame (a trace
// apitrace and oovr read, cut at a chunk's end; the calls of the next frame
// in that chunk stay). Returns the bytes kept. Error when the trace has no
// such frame or a file cannot be read or written.
uint64_t cut_trace(const std::string& in, const std::string& out, int last_frame);

}  // namespace oovr::apitrace
