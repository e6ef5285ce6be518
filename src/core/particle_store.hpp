#pragma once
// One structure-of-arrays store for all particles. Every per-particle array is registered by name and
// type, so sorting, checkpointing and export loop over the registry instead of a hand-kept list.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "core/first_touch.hpp"
#include "core/real.hpp"

namespace varsph {

enum class ScalarType { Float64, Float32, Int64, Int32 };

template <class S>
constexpr ScalarType scalar_type_of() {
  if constexpr (std::is_same_v<S, double>) return ScalarType::Float64;
  else if constexpr (std::is_same_v<S, float>) return ScalarType::Float32;
  else if constexpr (std::is_same_v<S, std::int64_t>) return ScalarType::Int64;
  else if constexpr (std::is_same_v<S, std::int32_t>) return ScalarType::Int32;
  else static_assert(sizeof(S) == 0, "unsupported scalar type");
}

// What a field is for: export to VTU frames, store in checkpoints.
struct FieldFlags {
  bool exported = false;     // written to frames when output.fields asks for it (or by default)
  bool checkpointed = true;  // saved in checkpoints (false only for scratch recomputed every step)
};

class FieldBase {
 public:
  FieldBase(std::string name, int components, ScalarType type, FieldFlags flags)
      : name_(std::move(name)), components_(components), type_(type), flags_(flags) {}
  virtual ~FieldBase() = default;
  const std::string& name() const { return name_; }
  int components() const { return components_; }
  ScalarType scalar_type() const { return type_; }
  const FieldFlags& flags() const { return flags_; }
  virtual std::size_t size() const = 0;
  virtual void resize(std::size_t n) = 0;
  virtual const void* raw() const = 0;
  virtual void* raw() = 0;
  // out[k] = in[perm[k]] for every particle through `scratch` (at least size() elements of this field);
  // worksharing loops of the caller's parallel region (ParticleStore::permute).
  virtual void permute(std::span<const std::uint32_t> perm, std::vector<std::byte>& scratch) = 0;
  // Keeps the particles kept[0..m) in that order and shrinks to m: out[k] = in[kept[k]] (particle removal).
  virtual void compact(std::span<const std::uint32_t> kept) = 0;
  // Appends copies of the particles src[0..k) at the end, in that order (particle creation). Storage grows
  // by doubling: a run that creates a few particles per step allocates O(log N) times, not every step.
  virtual void append_copies(std::span<const std::uint32_t> src) = 0;
  std::size_t bytes_per_particle() const { return element_bytes_; }

 protected:
  std::size_t element_bytes_ = 0;

 private:
  std::string name_;
  int components_;
  ScalarType type_;
  FieldFlags flags_;
};

template <class T, class = void>
struct scalar_of {
  using type = T;
};
template <class T>
struct scalar_of<T, std::void_t<typename T::Scalar>> {
  using type = typename T::Scalar;
};

// T is a scalar (double, float, int32, int64) or an Eigen fixed-size vector of them.
template <class T>
class Field final : public FieldBase {
 public:
  using Scalar = typename scalar_of<T>::type;
  static constexpr int kComponents = std::is_arithmetic_v<T> ? 1 : int(sizeof(T) / sizeof(Scalar));

  Field(std::string name, FieldFlags flags)
      : FieldBase(std::move(name), kComponents, scalar_type_of<Scalar>(), flags) {
    element_bytes_ = sizeof(T);
  }
  std::size_t size() const override { return data.size(); }
  void resize(std::size_t n) override { first_touch_resize(data, n); }  // pages placed by the loops' threads
  const void* raw() const override { return data.data(); }
  void* raw() override { return data.data(); }
  // Called by ParticleStore::permute inside its parallel region: the two loops are worksharing loops of
  // that region (one fork/join for all fields), run serially if called outside a region.
  void permute(std::span<const std::uint32_t> perm, std::vector<std::byte>& scratch) override {
    const long n = long(data.size());
    T* tmp = reinterpret_cast<T*>(scratch.data());  // sized by ParticleStore::permute for the largest field
    T* d = data.data();
#pragma omp for schedule(static)
    for (long k = 0; k < n; ++k) tmp[k] = d[perm[std::size_t(k)]];
#pragma omp for schedule(static)
    for (long k = 0; k < n; ++k) d[k] = tmp[k];
  }
  void compact(std::span<const std::uint32_t> kept) override {
    // kept is ascending (stable compaction), so kept[k] >= k and the copy can run in place, front to back
    for (std::size_t k = 0; k < kept.size(); ++k) data[k] = data[kept[k]];
    data.resize(kept.size());
  }
  void append_copies(std::span<const std::uint32_t> src) override {
    const std::size_t n = data.size(), m = n + src.size();
    if (m > data.capacity()) {  // amortised: at least double, pages placed by the loops' threads
      first_touch_resize(data, std::max(m, 2 * data.capacity()));
      data.resize(n);
    }
    data.resize(m);
    for (std::size_t k = 0; k < src.size(); ++k) data[n + k] = data[src[k]];
  }
  T& operator[](std::size_t i) { return data[i]; }
  const T& operator[](std::size_t i) const { return data[i]; }

  std::vector<T> data;
};

class ParticleStore {
 public:
  ParticleStore() = default;
  ParticleStore(const ParticleStore&) = delete;
  ParticleStore& operator=(const ParticleStore&) = delete;

  // Registers a field (or returns the existing one of the same name and type).
  template <class T>
  Field<T>& add(const std::string& name, FieldFlags flags = {}) {
    if (FieldBase* f = find(name)) {
      auto* typed = dynamic_cast<Field<T>*>(f);
      if (!typed) throw std::logic_error("field '" + name + "' registered twice with different types");
      return *typed;
    }
    auto field = std::make_unique<Field<T>>(name, flags);
    field->resize(size_);
    Field<T>& ref = *field;
    fields_.push_back(std::move(field));
    return ref;
  }

  template <class T>
  Field<T>& get(const std::string& name) {
    auto* typed = dynamic_cast<Field<T>*>(find(name));
    if (!typed) throw std::logic_error("no field '" + name + "' of the requested type");
    return *typed;
  }

  FieldBase* find(const std::string& name) {
    for (auto& f : fields_)
      if (f->name() == name) return f.get();
    return nullptr;
  }
  const FieldBase* find(const std::string& name) const {
    for (auto& f : fields_)
      if (f->name() == name) return f.get();
    return nullptr;
  }

  std::size_t size() const { return size_; }
  void resize(std::size_t n) {
    size_ = n;
    for (auto& f : fields_) f->resize(n);
  }
  // Reorders every registered field: new[k] = old[perm[k]]. One parallel region for all fields (a
  // fork/join per field and loop cost more than the copies themselves on small cases).
  void permute(std::span<const std::uint32_t> perm) {
    std::size_t bytes = 0;
    for (auto& f : fields_) bytes = std::max(bytes, f->bytes_per_particle() * size_);
    // grows by doubling, then reused: no allocation per step, also when particles are created every step
    if (bytes > scratch_.size()) first_touch_resize(scratch_, std::max(bytes, 2 * scratch_.size()));
    if (in_team()) {  // a step's region (core/team.hpp): the fields' loops are its worksharing loops
      for (auto& f : fields_) f->permute(perm, scratch_);
      return;
    }
#pragma omp parallel
    for (auto& f : fields_) f->permute(perm, scratch_);
  }
  // Removes particles: keeps only the indices in `kept` (strictly ascending, so the order of the survivors
  // is unchanged and the stable `id` field travels with them) in every registered field.
  void compact(std::span<const std::uint32_t> kept) {
    for (std::size_t k = 1; k < kept.size(); ++k)
      if (kept[k] <= kept[k - 1]) throw std::logic_error("ParticleStore::compact: indices not strictly ascending");
    if (!kept.empty() && kept.back() >= size_) throw std::logic_error("ParticleStore::compact: index out of range");
    for (auto& f : fields_) f->compact(kept);
    size_ = kept.size();
  }
  // Creates particles: appends copies of the particles src[0..k) (any order, repeats allowed) at the end
  // of every registered field and returns the index of the first copy. The caller gives the copies their
  // own identity (Simulation::create_particles draws new ids from the run's counter) and sorts after.
  std::size_t append_copies(std::span<const std::uint32_t> src) {
    for (const std::uint32_t i : src)
      if (i >= size_) throw std::logic_error("ParticleStore::append_copies: index out of range");
    const std::size_t first = size_;
    for (auto& f : fields_) f->append_copies(src);
    size_ += src.size();
    return first;
  }
  const std::vector<std::unique_ptr<FieldBase>>& fields() const { return fields_; }

  // Memory held by the particle arrays (for the bytes-per-particle report).
  std::size_t bytes() const {
    std::size_t b = 0;
    for (auto& f : fields_) b += f->bytes_per_particle() * size_;
    return b;
  }

 private:
  std::size_t size_ = 0;
  std::vector<std::unique_ptr<FieldBase>> fields_;
  std::vector<std::byte> scratch_;
};

}  // namespace varsph
