#include "spinewatch/anthropometry/split.hpp"

namespace spinewatch::anthropometry {

std::string_view to_string(Partition partition) { return partition == Partition::Test ? "test" : "train"; }

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

Partition partition_of(int subject_id) {
  return splitmix64(std::uint64_t(subject_id)) % 10 < 3 ? Partition::Test : Partition::Train;
}

std::vector<AnsurSubject> subjects_in(const std::vector<AnsurSubject>& subjects, Partition partition) {
  std::vector<AnsurSubject> out;
  for (const AnsurSubject& s : subjects)
    if (partition_of(s.id) == partition) out.push_back(s);
  return out;
}

}  // namespace spinewatch::anthropometry
