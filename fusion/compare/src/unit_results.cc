#include "wearscar/fusion/unit_results.h"

namespace wearscar::fusion {

void UnitResults::Put(std::string kind,
                      std::type_index type,
                      std::shared_ptr<const void> result) {
  for (Entry& e : entries_) {
    if (e.kind == kind) {
      e.type = type;
      e.result = std::move(result);
      return;
    }
  }
  entries_.push_back({std::move(kind), type, std::move(result)});
}

const void* UnitResults::Of(std::string_view kind) const {
  for (const Entry& e : entries_) {
    if (e.kind == kind) return e.result.get();
  }
  return nullptr;
}

}  // namespace wearscar::fusion
