// Stencils of the refined points of a patch table (all levels), each on the control
// vertices or on earlier points.
//
// Far::StencilTableFactory composes every stencil down to the control vertices, and its
// builder searches the stencil under construction for every weight it adds. Around a vertex
// of valence n about 4n points per level depend on it, each with a stencil of about n
// entries: n^2 memory per level and n^3 time (a fan of valence 256 took 20 s, valence 1000
// did not finish). Here a refined point's stencil is composed down to the control vertices
// (in a dense scratch row, linear in its sources' sizes) only while it stays small; a point
// whose stencil would pass kComposeLimit keeps its refinement weights on the previous
// level's points instead, and so do the points computed from it. Evaluation walks the points
// in order, so both forms cost their size; the table stays linear in the refined mesh.
// Memory is bounded by a budget checked before every stencil is stored.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/topologyRefiner.h>

namespace surfkit_osd {

using OpenSubdiv::Far::PrimvarRefinerReal;
using OpenSubdiv::Far::StencilTableReal;
using OpenSubdiv::Far::TopologyRefiner;

// One weight of a refined vertex on a vertex of the previous level, or on a vertex of its
// own level already computed (Catmull–Clark edge points use the child face points);
// src < 0 records a Clear() (the vertex starts over).
struct RecordedWeight {
  int dst;
  int src;
  bool src_is_child;
  double weight;
};

// The point type PrimvarRefiner interpolates: it records weights instead of summing points.
struct WeightRecorder {
  std::vector<RecordedWeight>* log = nullptr;
  int index = 0;
  bool child = false;
  void Clear(void* = nullptr) { log->push_back({index, -1, false, 0.0}); }
  void AddWithWeight(const WeightRecorder& src, double weight) {
    log->push_back({index, src.index, src.child, weight});
  }
};

class StencilComposer {
 public:
  // Largest stencil composed down to the control vertices (entries); larger ones stay on
  // the previous level's points.
  static constexpr size_t kComposeLimit = 128;

  // Stencils of points >= num_control, packed: stencil k covers
  // [offsets[k], offsets[k + 1]) of indices/weights.
  std::vector<size_t> offsets{0};
  std::vector<int> indices;
  std::vector<double> weights;

  StencilComposer(int num_control, size_t max_entries)
      : num_control_(num_control), max_entries_(max_entries),
        row_(static_cast<size_t>(num_control), 0.0),
        in_row_(static_cast<size_t>(num_control), 0) {}

  // True when the budget of entries stopped the composition.
  bool over_budget() const { return over_budget_; }

  // Appends the stencils of every refined vertex of levels 1..refiner.GetMaxLevel(), in
  // level order (the point numbering of Far::PatchTable with intermediate levels).
  std::string add_refined_levels(const TopologyRefiner& refiner) {
    PrimvarRefinerReal<double> primvar(refiner);
    std::vector<RecordedWeight> log;
    std::vector<WeightRecorder> src, dst;
    size_t previous_base = 0;  // stencil index of vertex 0 of the previous level (level >= 1)
    for (int level = 1; level <= refiner.GetMaxLevel(); ++level) {
      const int n_src = refiner.GetLevel(level - 1).GetNumVertices();
      const int n_dst = refiner.GetLevel(level).GetNumVertices();
      src.assign(static_cast<size_t>(n_src), WeightRecorder{});
      dst.assign(static_cast<size_t>(n_dst), WeightRecorder{});
      log.clear();
      for (int i = 0; i < n_src; ++i) src[static_cast<size_t>(i)] = {&log, i, false};
      for (int i = 0; i < n_dst; ++i) dst[static_cast<size_t>(i)] = {&log, i, true};
      WeightRecorder* from = src.data();
      WeightRecorder* to = dst.data();
      primvar.Interpolate(level, from, to);
      const size_t base = stencil_count();
      std::string why = compose_level(log, n_dst, n_src, level == 1, previous_base);
      if (!why.empty() || over_budget_) return why;
      previous_base = base;
    }
    return "";
  }

  size_t stencil_count() const { return offsets.size() - 1; }

 private:
  int num_control_;
  size_t max_entries_;
  bool over_budget_ = false;
  std::vector<double> row_;       // dense accumulator over control vertices
  std::vector<char> in_row_;      // row_[i] is part of the current stencil
  std::vector<int> touched_;      // control vertices of the current stencil, first-touch order

  void add_control(int cv, double w) {
    const size_t i = static_cast<size_t>(cv);
    if (!in_row_[i]) {
      in_row_[i] = 1;
      touched_.push_back(cv);
    }
    row_[i] += w;
  }

  // Adds w times point p (a control vertex, or a point with a composed stencil).
  void add_point(size_t p, double w) {
    if (p < static_cast<size_t>(num_control_)) {
      add_control(static_cast<int>(p), w);
      return;
    }
    const size_t k = p - static_cast<size_t>(num_control_);
    for (size_t e = offsets[k]; e < offsets[k + 1]; ++e) add_control(indices[e], w * weights[e]);
  }

  void clear_row() {
    for (int cv : touched_) {
      row_[static_cast<size_t>(cv)] = 0.0;
      in_row_[static_cast<size_t>(cv)] = 0;
    }
    touched_.clear();
  }

  // One level's stencils, by destination, before they are appended in index order; entries
  // are point indices (control vertices below num_control_).
  struct LevelRows {
    std::vector<size_t> offset, size;
    std::vector<char> composed;  // every entry a control vertex
    std::vector<int> indices;
    std::vector<double> weights;
  };

  std::vector<char> composed_;  // per stored stencil: on control vertices only

  std::string compose_level(const std::vector<RecordedWeight>& log, int n_dst, int n_src,
                            bool from_control, size_t previous_base) {
    const size_t nd = static_cast<size_t>(n_dst);
    const size_t ncv = static_cast<size_t>(num_control_);
    // Group the log by destination, keeping each destination's order (Clear first).
    std::vector<size_t> start(nd + 1, 0);
    std::vector<char> uses_child(nd, 0);
    for (const RecordedWeight& r : log) {
      if (r.dst < 0 || r.dst >= n_dst || r.src >= (r.src_is_child ? n_dst : n_src))
        return "refinement weight of vertex " + std::to_string(r.dst) + " on " +
               std::to_string(r.src) + " out of range at a level of " + std::to_string(n_dst) +
               " vertices refined from " + std::to_string(n_src);
      ++start[static_cast<size_t>(r.dst) + 1];
      if (r.src_is_child && r.src >= 0) uses_child[static_cast<size_t>(r.dst)] = 1;
    }
    for (size_t i = 0; i < nd; ++i) start[i + 1] += start[i];
    std::vector<size_t> order(log.size());
    {
      std::vector<size_t> next(start.begin(), start.end() - 1);
      for (size_t i = 0; i < log.size(); ++i) order[next[static_cast<size_t>(log[i].dst)]++] = i;
    }
    // The entries of destination d from its last Clear() on.
    auto entries_of = [&](size_t d) {
      size_t first = start[d];
      for (size_t j = start[d]; j < start[d + 1]; ++j)
        if (log[order[j]].src < 0) first = j + 1;
      return std::make_pair(first, start[d + 1]);
    };
    auto prev_point = [&](int src) {
      return from_control ? static_cast<size_t>(src)
                          : ncv + previous_base + static_cast<size_t>(src);
    };
    auto is_composed = [&](size_t point) { return point < ncv || composed_[point - ncv]; };

    // Vertices computed from the previous level only (face points) first, then those that
    // also use them (edge and vertex points of Catmull–Clark).
    LevelRows rows;
    rows.offset.assign(nd, 0);
    rows.size.assign(nd, 0);
    rows.composed.assign(nd, 0);
    for (int pass = 0; pass < 2; ++pass) {
      for (size_t d = 0; d < nd; ++d) {
        if (uses_child[d] != pass) continue;
        const auto [first, last] = entries_of(d);
        bool compose = true;
        for (size_t j = first; j < last && compose; ++j) {
          const RecordedWeight& r = log[order[j]];
          if (r.src_is_child) {
            const size_t c = static_cast<size_t>(r.src);
            if (uses_child[c])
              return "refined vertex " + std::to_string(d) + " depends on vertex " +
                     std::to_string(c) + " of its own level, which is not a face point";
            compose = rows.composed[c];
          } else {
            compose = is_composed(prev_point(r.src));
          }
        }
        if (compose) {
          for (size_t j = first; j < last; ++j) {
            const RecordedWeight& r = log[order[j]];
            if (r.src_is_child) {
              const size_t c = static_cast<size_t>(r.src);
              for (size_t e = rows.offset[c]; e < rows.offset[c] + rows.size[c]; ++e)
                add_control(rows.indices[e], r.weight * rows.weights[e]);
            } else {
              add_point(prev_point(r.src), r.weight);
            }
          }
          compose = touched_.size() <= kComposeLimit;
          if (!compose) clear_row();
        }
        const size_t begin = rows.indices.size();
        if (compose) {
          for (int cv : touched_) {
            rows.indices.push_back(cv);
            rows.weights.push_back(row_[static_cast<size_t>(cv)]);
          }
          clear_row();
        } else {
          // Weights on the previous level's points; a child face point is replaced by its
          // own entries, which lie on that level too (or on control vertices).
          for (size_t j = first; j < last; ++j) {
            const RecordedWeight& r = log[order[j]];
            if (r.src_is_child) {
              const size_t c = static_cast<size_t>(r.src);
              for (size_t e = rows.offset[c]; e < rows.offset[c] + rows.size[c]; ++e) {
                const int index = rows.indices[e];
                const double weight = r.weight * rows.weights[e];
                rows.indices.push_back(index);
                rows.weights.push_back(weight);
              }
            } else {
              rows.indices.push_back(static_cast<int>(prev_point(r.src)));
              rows.weights.push_back(r.weight);
            }
          }
        }
        if (indices.size() + rows.indices.size() > max_entries_) {
          over_budget_ = true;
          return "";
        }
        rows.offset[d] = begin;
        rows.size[d] = rows.indices.size() - begin;
        rows.composed[d] = compose ? 1 : 0;
      }
    }
    for (size_t d = 0; d < nd; ++d) {
      const size_t b = rows.offset[d], e = b + rows.size[d];
      indices.insert(indices.end(), rows.indices.begin() + static_cast<std::ptrdiff_t>(b),
                     rows.indices.begin() + static_cast<std::ptrdiff_t>(e));
      weights.insert(weights.end(), rows.weights.begin() + static_cast<std::ptrdiff_t>(b),
                     rows.weights.begin() + static_cast<std::ptrdiff_t>(e));
      offsets.push_back(indices.size());
      composed_.push_back(rows.composed[d]);
    }
    return "";
  }
};

}  // namespace surfkit_osd
