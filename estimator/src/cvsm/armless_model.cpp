#include "cvsm/armless_model.hpp"

#include <vector>

namespace spinewatch::cvsm_detail {

BodyModel without_arms(const BodyModel& model) {
  BodyModel m = model;
  std::erase_if(m.chains, [&](const std::vector<int>& chain) {
    const int j = model.planes[static_cast<std::size_t>(chain.front())].joint;
    return j == static_cast<int>(JointId::ShoulderLeft) || j == static_cast<int>(JointId::ShoulderRight);
  });
  m.in_chain.assign(m.planes.size(), 0);
  for (const auto& chain : m.chains)
    for (const int p : chain) m.in_chain[static_cast<std::size_t>(p)] = 1;
  return m;
}

}  // namespace spinewatch::cvsm_detail
