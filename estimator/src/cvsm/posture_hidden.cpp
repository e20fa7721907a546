#include "cvsm/posture_hidden.hpp"

#include <limits>

#include "cvsm/occluder_edge.hpp"

namespace spinewatch::cvsm_detail {

CutSpanHidden::CutSpanHidden(XorCost& cost) : cost_(cost) {
  std::array<const BitMask*, 2> now{};
  for (const View view : {View::Frontal, View::Lateral}) {
    const std::size_t v = index_of(view);
    before_[v] = now[v] = cost.hidden(view);
    const BitMask* silhouette = cost.silhouette(view);
    if (!before_[v] || !silhouette) continue;
    // The same edge the tracker found: its floor test passed already, and
    // it is applied after the edge is chosen.
    if (const auto edge = find_occluder_edge(*silhouette, std::numeric_limits<double>::max())) {
      hidden_below(*edge, *silhouette, masks_[v], HiddenSpan::Cut);
      // Beside what the view cannot tell from the background, hidden before.
      for (int y = 0; y < masks_[v].height(); ++y) {
        std::uint64_t* row = masks_[v].row(y);
        const std::uint64_t* was = before_[v]->row(y);
        for (int w = 0; w < masks_[v].words_per_row(); ++w) row[w] |= was[w];
      }
      now[v] = &masks_[v];
    }
  }
  cost_.set_hidden(now[0], now[1]);
}

CutSpanHidden::~CutSpanHidden() { cost_.set_hidden(before_[0], before_[1]); }

}  // namespace spinewatch::cvsm_detail
