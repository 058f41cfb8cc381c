// The functional stereo pipeline. Structure follows llvmpipe's split
// (STYLE.md): triangle setup (setup.h) and binning into 16x16 tiles (here),
// then rasterisation of each tile's bin in draw order (raster.h), tiles in
// parallel. Each tile owns its framebuffer pixels and its part of the trace,
// so the result is the same for any number of threads.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <numeric>

#include "oovr/core/error.h"
#include "oovr/core/parallel.h"
#include "oovr/pipeline/pipeline.h"
#include "oovr/pipeline/raster.h"
#include "oovr/pipeline/sampler.h"
#include "oovr/pipeline/setup.h"
#include "oovr/pipeline/shader_cost.h"

namespace oovr {

using namespace detail;  // the stages of setup.h and raster.h

FrameOutput render_frame(const Scene& scene, const StereoView& view, const PipelineSettings& settings, int frame) {
  settings.validate();
  FrameOutput result;
  FrameTrace& trace = result.trace;
  trace.frame = frame;
  trace.frame_width = view.frame_width;
  trace.frame_height = view.frame_height;
  trace.tile_size = kTileSize;
  trace.tiles_x = (view.frame_width + kTileSize - 1) / kTileSize;
  trace.tiles_y = (view.frame_height + kTileSize - 1) / kTileSize;
  trace.line_bytes = settings.line_bytes;
  trace.texture_format = settings.texture_format;
  line_block_shape(settings.line_bytes, trace.block_w, trace.block_h);
  const std::vector<Object>& draws = scene.draws(frame);
  trace.objects.resize(draws.size());

  // Geometry: objects in parallel, each into its own list, then concatenated
  // in draw order so that bins keep draw order.
  std::vector<std::vector<SetupTri>> per_object(draws.size());
  std::vector<std::vector<LitTri>> per_object_lit(draws.size());
  const unsigned threads = settings.threads ? settings.threads : default_thread_count();
  {
    const size_t chunks = std::min<size_t>(draws.size(), size_t(threads) * 8);
    parallel_for(chunks, threads, [&](size_t c) {
      GeometryStage stage(scene, draws, view);
      const size_t begin = draws.size() * c / chunks, end = draws.size() * (c + 1) / chunks;
      for (size_t o = begin; o < end; ++o) stage.run(uint32_t(o), per_object[o], per_object_lit[o], trace.objects[o]);
    });
  }
  std::vector<SetupTri> tris;
  std::vector<LitTri> lit;
  {
    size_t n = 0;
    for (const auto& v : per_object) n += v.size();
    tris.reserve(n);
    for (size_t o = 0; o < per_object.size(); ++o) {
      const uint32_t base = uint32_t(lit.size());
      for (SetupTri& t : per_object[o])
        if (t.lit != SetupTri::kNoLit) t.lit += base;
      tris.insert(tris.end(), per_object[o].begin(), per_object[o].end());
      lit.insert(lit.end(), per_object_lit[o].begin(), per_object_lit[o].end());
      std::vector<SetupTri>().swap(per_object[o]);
      std::vector<LitTri>().swap(per_object_lit[o]);
    }
  }

  // Binning: a triangle goes to every tile its box overlaps unless one of its
  // edges has the whole tile outside.
  const int tiles_x = trace.tiles_x, tiles_y = trace.tiles_y;
  std::vector<std::vector<uint32_t>> bins(size_t(tiles_x) * tiles_y);
  for (uint32_t id = 0; id < tris.size(); ++id) {
    const SetupTri& t = tris[id];
    for (int ty = t.miny / kTileSize; ty <= t.maxy / kTileSize; ++ty)
      for (int tx = t.minx / kTileSize; tx <= t.maxx / kTileSize; ++tx) {
        const int px0 = std::max(t.minx, tx * kTileSize), px1 = std::min(t.maxx, tx * kTileSize + kTileSize - 1);
        const int py0 = std::max(t.miny, ty * kTileSize), py1 = std::min(t.maxy, ty * kTileSize + kTileSize - 1);
        bool outside = false;
        for (int i = 0; i < 3 && !outside; ++i) {
          const int64_t ex = t.a[i] > 0 ? px1 : px0, ey = t.b[i] > 0 ? py1 : py0;
          outside = t.a[i] * ex + t.b[i] * ey + t.c[i] + t.bias[i] < 0;
        }
        if (!outside) bins[size_t(ty) * tiles_x + tx].push_back(id);
      }
  }

  // Rasterisation: tiles in parallel. Each clears and writes every pixel of
  // its own, so the frame's buffers are allocated untouched: their pages are
  // first written, and faulted in, by the tiles' threads.
  if (settings.draw_image) {
    result.colour = Image(view.frame_width, view.frame_height, Image::Unset{});
    result.object_id.resize(size_t(view.frame_width) * size_t(view.frame_height));
  }
  std::vector<detail::SamplerTexture> textures;
  textures.reserve(scene.textures.size());
  for (size_t i = 0; i < scene.textures.size(); ++i) {
    int bw = 0, bh = 0;
    texture_line_shape(scene.textures[i], settings.texture_format, settings.line_bytes, bw, bh);
    textures.emplace_back(uint32_t(i), scene.textures[i], bw, bh);
  }
  // Each texture's shape (SamplerTexture::shape), numbered from 1 by first
  // appearance: what its footprints, levels and texel blocks depend on.
  {
    std::map<std::vector<int>, uint32_t> shapes;
    for (detail::SamplerTexture& t : textures) {
      std::vector<int> key = {t.repeat, t.mipmapped, t.max_level, t.block_shift_x, t.block_shift_y};
      for (const detail::LevelView& l : t.levels) {
        key.push_back(l.width);
        key.push_back(l.height);
      }
      t.shape = shapes.emplace(std::move(key), uint32_t(shapes.size() + 1)).first->second;
    }
  }
  // Each draw's pass, its layers' coordinate transforms at this frame's time.
  const double seconds = scene.camera.seconds(frame);
  std::vector<PreparedPass> passes(draws.size());
  for (size_t o = 0; o < draws.size(); ++o) {
    const Pass& pass = scene.pass_of(draws[o]);
    PreparedPass& pp = passes[o];
    pp.pass = &pass;
    pp.coloured = uses_vertex_colours(scene, draws[o]);
    pp.replace = !pass.layers.empty() && pass.layers.front().combine == Combine::replace;
    for (const TextureLayer& l : pass.layers) {
      const UvTransform xf = l.transform(seconds);
      const bool lm = l.coords == TexCoords::lightmap;
      pp.layers.push_back({&textures[size_t(l.texture)], lm, !xf.identity(), xf, l.combine, l.scale});
      pp.lightmap_coords = pp.lightmap_coords || lm;
    }
    if (pass.shading == Shading::deluxe) {
      if (pass.layers.size() > kMaxDeluxeLayers)
        throw Error("a per-pixel lit pass samples " + std::to_string(pass.layers.size()) + " layers; at most " +
                    std::to_string(kMaxDeluxeLayers) + " are supported");
      pp.diffuse = pass.layer(LayerKind::diffuse);
      pp.normal = pass.layer(LayerKind::normal);
      pp.gloss = pass.layer(LayerKind::gloss);
      pp.glow = pass.layer(LayerKind::glow);
      pp.lightmap = pass.layer(LayerKind::lightmap);
      pp.deluxe = pass.layer(LayerKind::deluxe);
      if (pp.diffuse < 0 || pp.lightmap < 0 || pp.deluxe < 0)
        throw Error("a per-pixel lit pass needs diffuse, lightmap and deluxe layers");
    }
    trace.objects[o].fragment_instructions = fragment_instructions(pass);
    trace.objects[o].texture_layers = uint32_t(pass.layers.size());
  }
  // Tiles go to threads in runs along a row: neighbouring tiles on one
  // thread share its cache's texture lines, and threads rarely work side by
  // side. Each tile's records and lines go to a list of the thread's own
  // before they are moved to the tile's slot (slots share host cache lines).
  std::vector<TileRasterizer::Output> outputs(bins.size());
  constexpr size_t kRun = 8;
  const TileRasterizer::Frame target{settings.draw_image ? result.colour.rgba.data() : nullptr,
                                     settings.draw_image ? result.object_id.data() : nullptr, view.frame_width,
                                     view.frame_height};
  parallel_for((bins.size() + kRun - 1) / kRun, threads, [&](size_t run) {
    TileRasterizer r(tris, lit, passes, settings, trace.block_w, trace.block_h, target);
    for (size_t i = run * kRun; i < std::min(bins.size(), run * kRun + kRun); ++i) {
      TileRasterizer::Output own;
      r.run(int(i % size_t(tiles_x)), int(i / size_t(tiles_x)), bins[i], own);
      outputs[i] = std::move(own);
    }
  });

  // Merge the tiles' records into (object, eye, tile) order.
  struct Ref {
    uint32_t tile;
    uint32_t index;
  };
  // A tile holds at most one record per object and eye (an object's
  // triangles are binned eye after eye, each eye's together), so the order
  // is that of a counting sort by (object, eye) over the tiles in turn.
  const size_t eyes = size_t(view.eyes), keys = draws.size() * eyes;
  std::vector<uint32_t> first(keys + 1, 0);  // per (object, eye): its first record's place
  size_t records = 0;
  for (const TileRasterizer::Output& o : outputs) {
    records += o.work.size();
    for (const TileWork& w : o.work) ++first[size_t(w.object) * eyes + w.eye + 1];
  }
  for (size_t k = 0; k < keys; ++k) first[k + 1] += first[k];
  std::vector<Ref> refs(records);
  for (uint32_t i = 0; i < outputs.size(); ++i)
    for (uint32_t k = 0; k < outputs[i].work.size(); ++k) {
      const TileWork& w = outputs[i].work[k];
      refs[first[size_t(w.object) * eyes + w.eye]++] = {i, k};
    }
  // Each record's place in the frame's line list, then the copies in
  // parallel (they are most of the merge's time).
  trace.tiles.resize(refs.size());
  std::vector<uint64_t> begins(refs.size());
  uint64_t total_lines = 0;
  for (size_t k = 0; k < refs.size(); ++k) {
    begins[k] = total_lines;
    total_lines += outputs[refs[k].tile].work[refs[k].index].tex_count;
  }
  trace.tex_lines.resize(size_t(total_lines));
  const size_t chunks = std::min<size_t>(refs.size(), size_t(threads) * 8);
  parallel_for(chunks, threads, [&](size_t c) {
    for (size_t k = refs.size() * c / chunks; k < refs.size() * (c + 1) / chunks; ++k) {
      const TileRasterizer::Output& src = outputs[refs[k].tile];
      TileWork w = src.work[refs[k].index];
      if (w.tex_count) std::memcpy(&trace.tex_lines[begins[k]], &src.lines[w.tex_begin], w.tex_count * sizeof(TexLine));
      w.tex_begin = begins[k];
      trace.tiles[k] = w;
    }
  });
  return result;
}

}  // namespace oovr
