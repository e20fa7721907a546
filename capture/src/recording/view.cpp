#include "spinewatch/capture/recording.hpp"

namespace spinewatch {

std::string_view to_string(View view) { return view == View::Frontal ? "frontal" : "lateral"; }

}  // namespace spinewatch
