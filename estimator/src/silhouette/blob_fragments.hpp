// Which blobs of a silhouette are pieces of the subject rather than
// something else: where the subject's clothes match the backdrop (a dark
// shirt in front of a dark shirt in a photograph, a pale face against a
// pale wall), the thresholded subject falls apart into stacked pieces —
// head, trunk sides, legs — each a blob. A second person or an object
// beside the subject stands in other columns.
#pragma once

#include <algorithm>

namespace spinewatch::silhouette_detail {

struct BlobBox {
  int x_min = 0, x_max = -1, y_min = 0, y_max = -1;

  int width() const { return x_max - x_min + 1; }
  int height() const { return y_max - y_min + 1; }
  void add(int y, int x0, int x1) {
    if (x_max < x_min) {
      *this = {x0, x1, y, y};
      return;
    }
    x_min = std::min(x_min, x0);
    x_max = std::max(x_max, x1);
    y_min = std::min(y_min, y);
    y_max = std::max(y_max, y);
  }
};

// A fragment of the subject (the largest blob, `subject`): at least half
// of its columns are the subject's, it is no taller than the subject, and
// the rows between the two are at most half of the rows the two span
// together (a head cut off at the neck, legs cut off below a trunk that
// matches the backdrop: a body is not mostly missing band).
inline bool is_fragment_of(const BlobBox& piece, const BlobBox& subject) {
  const int shared_columns = std::min(piece.x_max, subject.x_max) - std::max(piece.x_min, subject.x_min) + 1;
  if (2 * shared_columns < piece.width() || piece.height() > subject.height()) return false;
  const int gap = std::max({0, piece.y_min - subject.y_max - 1, subject.y_min - piece.y_max - 1});
  const int spanned = std::max(piece.y_max, subject.y_max) - std::min(piece.y_min, subject.y_min) + 1;
  return 2 * gap <= spanned;
}

}  // namespace spinewatch::silhouette_detail
