// Splitting a range of trials over processes, and the two small agreements built on the
// word exchange of a ProcessGroup (vcmm/uncertainty/process_group.h).
#include "vcmm/uncertainty/process_group.h"

#include <algorithm>
#include <array>
#include <string>

#include "vcmm/uncertainty/errors.h"

namespace vcmm::uncertainty {

TrialPart trial_part(std::uint64_t begin, std::uint64_t end, unsigned rank, unsigned size) {
  if (size == 0 || rank >= size || end < begin) {
    throw InvalidInput("trial_part: need 0 <= rank < size and begin <= end; got rank " +
                       std::to_string(rank) + ", size " + std::to_string(size) + ", [" +
                       std::to_string(begin) + ", " + std::to_string(end) + ")");
  }
  const std::uint64_t n = end - begin, base = n / size, extra = n % size;
  const auto start = [&](std::uint64_t r) { return begin + r * base + std::min(r, extra); };
  return {start(rank), start(rank + 1u)};
}

bool decision_of_first(ProcessGroup* group, bool flag) {
  if (group == nullptr) return flag;
  const std::array<std::uint64_t, 1> mine{flag ? 1u : 0u};
  return group->all_gather(mine).at(0) != 0;
}

bool any_process(ProcessGroup* group, bool flag) {
  if (group == nullptr) return flag;
  const std::array<std::uint64_t, 1> mine{flag ? 1u : 0u};
  const std::vector<std::uint64_t> all = group->all_gather(mine);
  return std::any_of(all.begin(), all.end(), [](std::uint64_t w) { return w != 0; });
}

}  // namespace vcmm::uncertainty
