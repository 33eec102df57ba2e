#pragma once
// The results of a test's analysis units (wearscar/fusion/unit.h) by kind:
// the container knows no analysis. Each unit's result is stored once, by
// the pipeline that ran the unit, under its kind (result.json's key) and
// its type; readers ask by type (Find, Get) and never by a field.

#include <memory>
#include <string>
#include <string_view>
#include <typeindex>
#include <utility>
#include <vector>

namespace wearscar::fusion {

class UnitResults {
 public:
  // Stores `result` as the unit `kind`'s; a kind stored again replaces it.
  template <typename R>
  void Put(std::string kind, std::shared_ptr<const R> result) {
    Put(std::move(kind), std::type_index(typeid(R)), std::move(result));
  }
  void Put(std::string kind,
           std::type_index type,
           std::shared_ptr<const void> result);

  // The result of type R, or nullptr when its unit did not run.
  template <typename R>
  const R* Find() const {
    for (const Entry& e : entries_) {
      if (e.type == std::type_index(typeid(R)))
        return static_cast<const R*>(e.result.get());
    }
    return nullptr;
  }
  // The same, or R's empty value (a map without bins, no lines) when its
  // unit did not run: for readers that draw or list what there is.
  template <typename R>
  const R& Get() const {
    static const R kNone{};
    const R* r = Find<R>();
    return r ? *r : kNone;
  }
  // The result of type R shared (null when its unit did not run): for a
  // reader that keeps it beyond this container (the comparison keeps the
  // spring check's).
  template <typename R>
  std::shared_ptr<const R> Share() const {
    for (const Entry& e : entries_) {
      if (e.type == std::type_index(typeid(R)))
        return std::static_pointer_cast<const R>(e.result);
    }
    return nullptr;
  }
  // The result stored under `kind` (null when its unit did not run): for
  // the unit itself, which knows its type.
  const void* Of(std::string_view kind) const;
  bool Has(std::string_view kind) const { return Of(kind) != nullptr; }

 private:
  struct Entry {
    std::string kind;
    std::type_index type;
    std::shared_ptr<const void> result;
  };
  std::vector<Entry> entries_;
};

}  // namespace wearscar::fusion
