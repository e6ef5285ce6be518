// HDF5 checkpoints through the C API. Datasets are chunked with the Fletcher-32 filter and the file uses
// the 1.8+ object header format (metadata checksums); on top of that a 64-bit content digest over every
// value the reader returns (attributes, texts, arrays) is stored as the root attribute `content_digest`,
// so a flipped bit that HDF5 does not see still cannot give a wrong state, and every size the file claims
// is bounded by the file's size before HDF5 allocates it (the 1.8 chunk index has no checksum).
#include "io/checkpoint.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <regex>
#include <sstream>

#include "core/errors.hpp"
#include "io/atomic_file.hpp"

namespace varsph::io {
namespace {

constexpr const char* kMagic = "varsph-checkpoint";
constexpr const char* kPieceMagic = "varsph-checkpoint-piece";

// Owns one HDF5 identifier (closed through the generic reference count).
class Handle {
 public:
  Handle() = default;
  explicit Handle(hid_t id) : id_(id) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : id_(o.id_) { o.id_ = -1; }
  ~Handle() {
    if (id_ >= 0) H5Idec_ref(id_);
  }
  hid_t get() const { return id_; }
  bool ok() const { return id_ >= 0; }
  hid_t release() {
    const hid_t id = id_;
    id_ = -1;
    return id;
  }

 private:
  hid_t id_ = -1;
};

void silence_hdf5() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

// Content digest: 8-byte words mixed by (h ^ w) * odd constant and an xorshift, each step a bijection
// in h and in w, so changing any one word of the input always changes the result. Lengths are mixed
// in first, so field boundaries count too. Not cryptographic: it guards against damage, not forgery.
class Digest {
 public:
  void bytes(const void* data, std::size_t n) {
    word(n);
    const auto* p = static_cast<const unsigned char*>(data);
    std::size_t k = 0;
    for (; k + 8 <= n; k += 8) {
      std::uint64_t w;
      std::memcpy(&w, p + k, 8);
      word(w);
    }
    std::uint64_t tail = 0;
    if (n > k) std::memcpy(&tail, p + k, n - k);  // an empty array may have no storage (nullptr)
    word(tail);
  }
  void text(const std::string& s) { bytes(s.data(), s.size()); }
  template <class T>
  void value(const T& v) { bytes(&v, sizeof v); }
  std::uint64_t result() const { return h_; }

 private:
  void word(std::uint64_t w) {
    h_ = (h_ ^ w) * 0x9E3779B97F4A7C15ull;
    h_ ^= h_ >> 29;
  }
  std::uint64_t h_ = 0xCBF29CE484222325ull;
};

// The header part of the digest, in the order the reader sees the values.
void digest_header(Digest& d, const CheckpointHeader& h, const std::string& scene, const std::string& integ,
                   const std::string& runner, const std::string& order) {
  d.value(h.format_version);
  d.text(h.program_version);
  d.text(h.real_type);
  d.value(h.dimension);
  d.value(h.step);
  d.value(h.time);
  d.value(h.dt);
  d.value(h.particles);
  d.text(h.integrator);
  d.text(scene);
  d.text(integ);
  d.text(runner);
  d.text(order);
}

hid_t native_type(ScalarType t) {
  switch (t) {
    case ScalarType::Float64: return H5T_NATIVE_DOUBLE;
    case ScalarType::Float32: return H5T_NATIVE_FLOAT;
    case ScalarType::Int64: return H5T_NATIVE_INT64;
    case ScalarType::Int32: return H5T_NATIVE_INT32;
  }
  return H5T_NATIVE_DOUBLE;
}
std::size_t scalar_bytes(ScalarType t) {
  return (t == ScalarType::Float64 || t == ScalarType::Int64) ? 8 : 4;
}
const char* type_name(ScalarType t) {
  switch (t) {
    case ScalarType::Float64: return "float64";
    case ScalarType::Float32: return "float32";
    case ScalarType::Int64: return "int64";
    case ScalarType::Int32: return "int32";
  }
  return "?";
}

// ---------------------------------------------------------------------------------------------- write

struct Writer {
  std::string file;  // for messages
  [[noreturn]] void fail(const std::string& what) const {
    throw IoError(file + ": cannot write the checkpoint (" + what + "; disk full or not writable?)");
  }
  void check(herr_t e, const std::string& what) const {
    if (e < 0) fail(what);
  }
  hid_t check_id(hid_t id, const std::string& what) const {
    if (id < 0) fail(what);
    return id;
  }

  template <class T>
  void attr(hid_t obj, const char* name, hid_t type, const T& value) const {
    Handle space(check_id(H5Screate(H5S_SCALAR), "dataspace"));
    Handle a(check_id(H5Acreate2(obj, name, type, space.get(), H5P_DEFAULT, H5P_DEFAULT), name));
    check(H5Awrite(a.get(), type, &value), name);
  }
  void attr_string(hid_t obj, const char* name, const std::string& value) const {
    Handle type(check_id(H5Tcopy(H5T_C_S1), "string type"));
    check(H5Tset_size(type.get(), std::max<std::size_t>(1, value.size())), "string type");
    Handle space(check_id(H5Screate(H5S_SCALAR), "dataspace"));
    Handle a(check_id(H5Acreate2(obj, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT), name));
    std::string padded = value.empty() ? std::string(1, '\0') : value;
    check(H5Awrite(a.get(), type.get(), padded.data()), name);
  }

  // A chunked, checksummed dataset of `rows` x `components` scalars.
  void dataset(hid_t group, const std::string& name, hid_t type, std::size_t rows, int components,
               const void* data) const {
    hsize_t dims[2] = {hsize_t(rows), hsize_t(components)};
    const int rank = components == 1 ? 1 : 2;
    Handle space(check_id(H5Screate_simple(rank, dims, nullptr), "dataspace " + name));
    Handle dcpl(check_id(H5Pcreate(H5P_DATASET_CREATE), "properties " + name));
    if (rows > 0) {
      hsize_t chunk[2] = {std::min<hsize_t>(rows, 65536), hsize_t(components)};
      check(H5Pset_chunk(dcpl.get(), rank, chunk), "chunking " + name);
      check(H5Pset_fletcher32(dcpl.get()), "checksum filter " + name);
    }
    Handle d(check_id(H5Dcreate2(group, name.c_str(), type, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
                      "dataset " + name));
    if (rows > 0) check(H5Dwrite(d.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), "writing " + name);
  }
  void text(hid_t group, const std::string& name, const std::string& value) const {
    dataset(group, name, H5T_NATIVE_CHAR, value.size(), 1, value.data());
  }
};

// What one HDF5 file of a checkpoint holds: a whole checkpoint (header and particles), the manifest of
// a checkpoint in pieces (header and the particle count of every piece) or one piece (particles).
struct FileContent {
  const CheckpointHeader* header = nullptr;         // whole checkpoint or manifest
  const ParticleStore* store = nullptr;             // field list (and particles unless a manifest)
  std::size_t count = 0;                            // particle rows written from the store
  const std::vector<std::int64_t>* pieces = nullptr;  // manifest: particles per piece
  int piece = -1;                                   // piece: its number
};

void write_file(const std::filesystem::path& tmp, const std::string& shown, const FileContent& c) {
  silence_hdf5();
  const Writer w{shown};
  Handle fapl(w.check_id(H5Pcreate(H5P_FILE_ACCESS), "file properties"));
  // 1.8+ object headers carry checksums: corrupted metadata is detected on read. Not the 1.10 format:
  // with HDF5 1.10.8 a disk-full failure then leaves datasets that H5_term_library crashes on at exit
  // (IoFailure.DiskFullGivesExit4AndLeavesNoPartialFile); the content digest covers what 1.10 would add
  w.check(H5Pset_libver_bounds(fapl.get(), H5F_LIBVER_V18, H5F_LIBVER_LATEST), "file format bounds");
  const hid_t fid = H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get());
  if (fid < 0) w.fail("cannot create " + tmp.string());
  try {
    const hid_t root = fid;
    const ParticleStore& store = *c.store;
    Digest digest;  // content_digest: what the reader will see of this file, in its order
    std::string order;
    for (const auto& f : store.fields())
      if (f->flags().checkpointed) order += (order.empty() ? "" : "\n") + f->name();
    if (c.header) {
      const CheckpointHeader& h = *c.header;
      w.attr_string(root, "format", kMagic);
      // a checkpoint in pieces has its own format version (older readers refuse it instead of misreading it)
      const int version = c.pieces ? kCheckpointPiecesFormatVersion : h.format_version;
      w.attr(root, "format_version", H5T_NATIVE_INT, version);
      w.attr_string(root, "program_version", h.program_version);
      w.attr_string(root, "real", h.real_type);
      w.attr(root, "dimension", H5T_NATIVE_INT, h.dimension);
      w.attr(root, "step", H5T_NATIVE_INT64, h.step);
      w.attr(root, "time", H5T_NATIVE_DOUBLE, h.time);
      w.attr(root, "dt", H5T_NATIVE_DOUBLE, h.dt);
      std::int64_t n = std::int64_t(c.count);
      if (c.pieces) {
        n = 0;
        for (auto k : *c.pieces) n += k;
        w.attr(root, "pieces", H5T_NATIVE_INT, int(c.pieces->size()));
      }
      w.attr(root, "particles", H5T_NATIVE_INT64, n);
      w.attr_string(root, "integrator", h.integrator);
      Handle meta(w.check_id(H5Gcreate2(fid, "meta", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), "group meta"));
      const std::string scene = h.scene.dump(), integ = h.integrator_state.dump(), runner = h.runner_state.dump();
      w.text(meta.get(), "scene", scene);
      w.text(meta.get(), "integrator_state", integ);
      w.text(meta.get(), "runner_state", runner);
      w.text(meta.get(), "field_order", order);
      if (c.pieces)
        w.dataset(meta.get(), "piece_particles", H5T_NATIVE_INT64, c.pieces->size(), 1, c.pieces->data());
      CheckpointHeader hd = h;
      hd.format_version = version;
      hd.particles = n;
      digest_header(digest, hd, scene, integ, runner, order);
      if (c.pieces) digest.bytes(c.pieces->data(), c.pieces->size() * sizeof(std::int64_t));
    } else {
      w.attr_string(root, "format", kPieceMagic);
      w.attr(root, "piece", H5T_NATIVE_INT, c.piece);
      const std::int64_t n = std::int64_t(c.count);
      w.attr(root, "particles", H5T_NATIVE_INT64, n);
      digest.value(c.piece);
      digest.value(n);
      digest.text(order);
    }
    if (!c.pieces) {
      Handle parts(
          w.check_id(H5Gcreate2(fid, "particles", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), "group particles"));
      for (const auto& f : store.fields()) {
        if (!f->flags().checkpointed) continue;
        w.dataset(parts.get(), f->name(), native_type(f->scalar_type()), c.count, f->components(), f->raw());
      }
      for (const auto& f : store.fields()) {
        if (!f->flags().checkpointed) continue;
        digest.text(f->name());
        digest.value(int(f->scalar_type()));
        digest.value(f->components());
        digest.bytes(f->raw(), f->bytes_per_particle() * c.count);
      }
    }
    w.attr(root, "content_digest", H5T_NATIVE_UINT64, digest.result());
    w.check(H5Fflush(fid, H5F_SCOPE_GLOBAL), "flushing");
  } catch (...) {
    H5Fclose(fid);
    throw;
  }
  w.check(H5Fclose(fid), "closing the file");
}

// ----------------------------------------------------------------------------------------------- read

struct Reader {
  std::string file;
  std::uintmax_t file_bytes = 0;  // nothing read from the file can be larger than the file
  void check_size(double bytes, const std::string& what) const {
    if (!(bytes <= double(file_bytes)))
      fail(what + " claims " + std::to_string(bytes) + " bytes, more than the file's " + std::to_string(file_bytes));
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(file + ": not a usable varsph checkpoint: " + what);
  }
  hid_t check_id(hid_t id, const std::string& what) const {
    if (id < 0) fail(what);
    return id;
  }
  template <class T>
  T attr(hid_t obj, const char* name, hid_t type) const {
    if (H5Aexists(obj, name) <= 0) fail(std::string("attribute '") + name + "' is missing");
    Handle a(check_id(H5Aopen(obj, name, H5P_DEFAULT), std::string("attribute '") + name + "' is unreadable"));
    T v{};
    if (H5Aread(a.get(), type, &v) < 0) fail(std::string("attribute '") + name + "' is unreadable");
    return v;
  }
  std::string attr_string(hid_t obj, const char* name) const {
    if (H5Aexists(obj, name) <= 0) fail(std::string("attribute '") + name + "' is missing");
    Handle a(check_id(H5Aopen(obj, name, H5P_DEFAULT), std::string("attribute '") + name + "' is unreadable"));
    Handle type(check_id(H5Aget_type(a.get()), name));
    if (H5Tget_class(type.get()) != H5T_STRING) fail(std::string("attribute '") + name + "' is not a string");
    const std::size_t size = H5Tget_size(type.get());
    check_size(double(size), std::string("attribute '") + name + "'");
    std::string s(size, '\0');
    if (H5Aread(a.get(), type.get(), s.data()) < 0) fail(std::string("attribute '") + name + "' is unreadable");
    s.resize(std::strlen(s.c_str()));
    return s;
  }
  // Every chunk the index lists must be stored in exactly its data plus the 4-byte Fletcher-32 checksum
  // (the only filter the writer sets). HDF5 1.10.8 runs the checksum filter over a chunk whose index
  // claims fewer than 4 bytes with a length of (bytes - 4) wrapped around: a segfault (one flipped bit,
  // found by test_checkpoint_damage_all; fuzz/regressions/checkpoint/refused_flip_chunk_size_2_bytes.h5).
  void check_chunks(hid_t d, hid_t space, const std::string& name, int rank, std::size_t scalar_size) const {
    Handle dcpl(check_id(H5Dget_create_plist(d), "dataset '" + name + "' properties"));
    if (H5Pget_layout(dcpl.get()) != H5D_CHUNKED) return;  // contiguous: no filter (the digest checks it)
    hsize_t chunk[2] = {0, 0};
    if (H5Pget_chunk(dcpl.get(), 2, chunk) != rank) fail("dataset '" + name + "' has an unreadable chunk shape");
    double chunk_bytes = double(scalar_size);
    for (int k = 0; k < rank; ++k) chunk_bytes *= double(chunk[k]);
    hsize_t n = 0;
    if (H5Dget_num_chunks(d, space, &n) < 0)  // HDF5 1.10.8 refuses H5S_ALL here
      fail("dataset '" + name + "' has an unreadable chunk index");
    for (hsize_t k = 0; k < n; ++k) {
      hsize_t offset[2] = {0, 0};
      unsigned filter_mask = 0;
      haddr_t address = 0;
      hsize_t stored = 0;
      if (H5Dget_chunk_info(d, space, k, offset, &filter_mask, &address, &stored) < 0)
        fail("dataset '" + name + "' has an unreadable chunk index");
      if (double(stored) != chunk_bytes + 4)
        fail("dataset '" + name + "' chunk " + std::to_string(k) + " is stored in " + std::to_string(stored) +
             " bytes, expected " + std::to_string(std::uint64_t(chunk_bytes) + 4) + " (its data and checksum)");
    }
  }
  // Reads a dataset of rows x components scalars of the given type; returns rows.
  std::vector<std::byte> dataset(hid_t group, const std::string& name, ScalarType type, std::int64_t rows,
                                 int& components_out, bool is_text = false) const {
    if (H5Lexists(group, name.c_str(), H5P_DEFAULT) <= 0) fail("dataset '" + name + "' is missing");
    Handle d(check_id(H5Dopen2(group, name.c_str(), H5P_DEFAULT), "dataset '" + name + "' is unreadable"));
    Handle space(check_id(H5Dget_space(d.get()), name));
    const int rank = H5Sget_simple_extent_ndims(space.get());
    if (rank < 1 || rank > 2) fail("dataset '" + name + "' has rank " + std::to_string(rank));
    hsize_t dims[2] = {0, 1};
    H5Sget_simple_extent_dims(space.get(), dims, nullptr);
    if (rows >= 0 && std::int64_t(dims[0]) != rows)
      fail("dataset '" + name + "' has " + std::to_string(dims[0]) + " rows, expected " + std::to_string(rows) +
           " (one per particle)");
    components_out = rank == 2 ? int(dims[1]) : 1;
    Handle ftype(check_id(H5Dget_type(d.get()), name));
    const H5T_class_t cls = H5Tget_class(ftype.get());
    const std::size_t fsize = H5Tget_size(ftype.get());
    const bool want_float = type == ScalarType::Float32 || type == ScalarType::Float64;
    if (!is_text && ((cls == H5T_FLOAT) != want_float || (cls != H5T_FLOAT && cls != H5T_INTEGER) ||
                     fsize != scalar_bytes(type)))
      fail("dataset '" + name + "' has another scalar type than " + type_name(type));
    check_size(double(dims[0]) * double(components_out) * double(is_text ? 1 : scalar_bytes(type)),
               "dataset '" + name + "'");
    // the chunk sizes the index records (HDF5 allocates them before the checksum is seen; the 1.8-format
    // chunk index of format-1 files carries no checksum of its own)
    check_size(double(H5Dget_storage_size(d.get())), "dataset '" + name + "' storage");
    const std::size_t count = std::size_t(dims[0]) * std::size_t(components_out);
    if (count > 0) check_chunks(d.get(), space.get(), name, rank, fsize);
    std::vector<std::byte> out(count * (is_text ? 1 : scalar_bytes(type)));
    if (count > 0 &&
        H5Dread(d.get(), is_text ? H5T_NATIVE_CHAR : native_type(type), H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
      fail("dataset '" + name + "' is corrupted (checksum or read error)");
    return out;
  }
  std::string text(hid_t group, const std::string& name) const {
    int comps = 1;
    const auto b = dataset(group, name, ScalarType::Int32, -1, comps, true);
    return std::string(reinterpret_cast<const char*>(b.data()), b.size());
  }
  nlohmann::json json_of(const std::string& text, const std::string& name) const {
    try {
      return nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception&) {
      fail("meta/" + name + " is not valid JSON");
    }
  }
};

}  // namespace

const CheckpointArray* Checkpoint::find(const std::string& name) const {
  for (const auto& a : arrays)
    if (a.name == name) return &a;
  return nullptr;
}

void write_checkpoint(const std::filesystem::path& path, const CheckpointHeader& header, const ParticleStore& store) {
  FileContent c;
  c.header = &header;
  c.store = &store;
  c.count = store.size();
  write_atomically(path, [&](const std::filesystem::path& tmp) { write_file(tmp, path.string(), c); });
}

std::filesystem::path checkpoint_pieces_dir(const std::filesystem::path& manifest) {
  return manifest.parent_path() / manifest.stem();
}

std::filesystem::path checkpoint_piece_path(const std::filesystem::path& manifest, int piece) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "piece_%06d.h5", piece);
  return checkpoint_pieces_dir(manifest) / buf;
}

void write_checkpoint_piece(const std::filesystem::path& manifest, int piece, const ParticleStore& store,
                            std::size_t count) {
  FileContent c;
  c.store = &store;
  c.count = count;
  c.piece = piece;
  const auto path = checkpoint_piece_path(manifest, piece);
  write_atomically(path, [&](const std::filesystem::path& tmp) { write_file(tmp, path.string(), c); });
}

void write_checkpoint_manifest(const std::filesystem::path& path, const CheckpointHeader& header,
                               const ParticleStore& store, const std::vector<std::int64_t>& piece_counts) {
  FileContent c;
  c.header = &header;
  c.store = &store;
  c.pieces = &piece_counts;
  write_atomically(path, [&](const std::filesystem::path& tmp) { write_file(tmp, path.string(), c); });
}

void remove_checkpoint(const std::filesystem::path& path) {
  std::error_code ec;
  std::filesystem::remove(path, ec);
  std::filesystem::remove_all(checkpoint_pieces_dir(path), ec);
}

Checkpoint read_checkpoint(const std::filesystem::path& path, int part, int parts) {
  silence_hdf5();
  Reader r{path.string()};
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(path.string() + ": checkpoint file not found (--restart expects DIR/checkpoints/step_N.h5)");
  r.file_bytes = std::filesystem::file_size(path, ec);
  if (H5Fis_hdf5(path.c_str()) <= 0) r.fail("not an HDF5 file (truncated or corrupted?)");
  Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  if (!file.ok()) r.fail("HDF5 cannot open it (truncated or corrupted?)");
  const hid_t fid = file.get();
  if (r.attr_string(fid, "format") != kMagic) r.fail("attribute 'format' is not \"varsph-checkpoint\"");
  Checkpoint c;
  CheckpointHeader& h = c.header;
  h.format_version = r.attr<int>(fid, "format_version", H5T_NATIVE_INT);
  if (h.format_version > kCheckpointPiecesFormatVersion)
    throw InputError(path.string() + ": checkpoint format version " + std::to_string(h.format_version) +
                     " is newer than this program reads (" + std::to_string(kCheckpointPiecesFormatVersion) +
                     "); use the varsph version that wrote it (" + r.attr_string(fid, "program_version") + ")");
  if (h.format_version < 1) r.fail("format_version " + std::to_string(h.format_version));
  h.program_version = r.attr_string(fid, "program_version");
  h.real_type = r.attr_string(fid, "real");
  h.dimension = r.attr<int>(fid, "dimension", H5T_NATIVE_INT);
  h.step = r.attr<std::int64_t>(fid, "step", H5T_NATIVE_INT64);
  h.time = r.attr<double>(fid, "time", H5T_NATIVE_DOUBLE);
  h.dt = r.attr<double>(fid, "dt", H5T_NATIVE_DOUBLE);
  h.particles = r.attr<std::int64_t>(fid, "particles", H5T_NATIVE_INT64);
  h.integrator = r.attr_string(fid, "integrator");
  if (h.particles < 0) r.fail("negative particle count");

  if (H5Lexists(fid, "meta", H5P_DEFAULT) <= 0) r.fail("group 'meta' is missing");
  Handle meta(r.check_id(H5Gopen2(fid, "meta", H5P_DEFAULT), "group 'meta' is unreadable"));
  const std::string scene = r.text(meta.get(), "scene"), integ = r.text(meta.get(), "integrator_state"),
                    runner = r.text(meta.get(), "runner_state");
  const std::string order = r.text(meta.get(), "field_order");
  Digest digest;
  digest_header(digest, h, scene, integ, runner, order);
  h.scene = r.json_of(scene, "scene");
  h.integrator_state = r.json_of(integ, "integrator_state");
  h.runner_state = r.json_of(runner, "runner_state");

  // Every field of `group` (one file), all `expected_rows` rows, added to `dg` as written.
  auto read_all = [&](const Reader& rd, hid_t group, std::int64_t expected_rows, Digest& dg) {
    std::vector<CheckpointArray> out;
    std::stringstream ss(order);
    std::string name;
    while (std::getline(ss, name)) {
      if (name.empty()) continue;
      Handle d(rd.check_id(H5Dopen2(group, name.c_str(), H5P_DEFAULT), "dataset '" + name + "' is missing"));
      Handle t(rd.check_id(H5Dget_type(d.get()), name));
      const H5T_class_t cls = H5Tget_class(t.get());
      const std::size_t sz = H5Tget_size(t.get());
      ScalarType st;
      if (cls == H5T_FLOAT && sz == 8) st = ScalarType::Float64;
      else if (cls == H5T_FLOAT && sz == 4) st = ScalarType::Float32;
      else if (cls == H5T_INTEGER && sz == 8) st = ScalarType::Int64;
      else if (cls == H5T_INTEGER && sz == 4) st = ScalarType::Int32;
      else rd.fail("dataset '" + name + "' has an unsupported scalar type");
      CheckpointArray a;
      a.name = name;
      a.type = st;
      a.bytes = rd.dataset(group, name, st, expected_rows, a.components);
      dg.text(a.name);
      dg.value(int(a.type));
      dg.value(a.components);
      dg.bytes(a.bytes.data(), a.bytes.size());
      out.push_back(std::move(a));
    }
    return out;
  };
  // Appends rows [lo, hi) of `from` (one file's arrays) to this reader's arrays.
  auto take_rows = [&](const Reader& rd, const std::vector<CheckpointArray>& from, std::int64_t lo, std::int64_t hi) {
    for (std::size_t k = 0; k < from.size(); ++k) {
      const CheckpointArray& a = from[k];
      if (k >= c.arrays.size()) {
        CheckpointArray e;
        e.name = a.name;
        e.type = a.type;
        e.components = a.components;
        c.arrays.push_back(std::move(e));
      }
      CheckpointArray& out = c.arrays[k];
      if (out.name != a.name || out.type != a.type || out.components != a.components)
        rd.fail("dataset '" + a.name + "' differs between pieces");
      const std::size_t row = scalar_bytes(a.type) * std::size_t(a.components);
      out.bytes.insert(out.bytes.end(), a.bytes.begin() + std::ptrdiff_t(std::size_t(lo) * row),
                       a.bytes.begin() + std::ptrdiff_t(std::size_t(hi) * row));
    }
  };
  auto check_digest = [](const Reader& rd, hid_t file_id, const Digest& dg) {
    if (rd.attr<std::uint64_t>(file_id, "content_digest", H5T_NATIVE_UINT64) != dg.result())
      rd.fail("content digest mismatch (the file was damaged after it was written)");
  };
  // this reader's share: rows [first, first + rows) of the particles (all of them for part 0 of 1);
  // every file it touches is read whole, so that its digest is checked
  c.first_row = h.particles * part / parts;
  c.rows = h.particles * (part + 1) / parts - c.first_row;
  if (H5Aexists(fid, "pieces") > 0) {
    // a checkpoint in pieces (distributed run): the rows are the pieces' particles in piece order
    if (h.format_version != kCheckpointPiecesFormatVersion)
      r.fail("attribute 'pieces' in a format " + std::to_string(h.format_version) + " file");
    const int pieces = r.attr<int>(fid, "pieces", H5T_NATIVE_INT);
    if (pieces < 1) r.fail("attribute 'pieces' is " + std::to_string(pieces));
    int one = 1;
    const auto raw = r.dataset(meta.get(), "piece_particles", ScalarType::Int64, pieces, one);
    digest.bytes(raw.data(), raw.size());
    check_digest(r, fid, digest);
    std::vector<std::int64_t> counts(static_cast<std::size_t>(pieces));
    std::memcpy(counts.data(), raw.data(), raw.size());
    std::int64_t begin = 0;
    for (int k = 0; k < pieces; ++k) {
      if (counts[std::size_t(k)] < 0) r.fail("piece " + std::to_string(k) + " has a negative particle count");
      const std::int64_t end = begin + counts[std::size_t(k)];
      const std::int64_t lo = std::max(begin, c.first_row), hi = std::min(end, c.first_row + c.rows);
      // pieces holding some of this reader's rows; piece 0 also when there are none (field shapes)
      if (lo < hi || (k == 0 && c.rows == 0)) {
        const auto piece = checkpoint_piece_path(path, k);
        Reader pr{piece.string()};
        pr.file_bytes = std::filesystem::file_size(piece, ec);
        if (ec || H5Fis_hdf5(piece.c_str()) <= 0)
          r.fail("piece " + std::to_string(k) + " (" + piece.string() + ") is missing or not an HDF5 file");
        Handle pf(H5Fopen(piece.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
        if (!pf.ok()) pr.fail("HDF5 cannot open it (truncated or corrupted?)");
        if (pr.attr_string(pf.get(), "format") != kPieceMagic) pr.fail("not a piece of a varsph checkpoint");
        if (pr.attr<int>(pf.get(), "piece", H5T_NATIVE_INT) != k) pr.fail("its piece number differs from its name");
        const auto n = pr.attr<std::int64_t>(pf.get(), "particles", H5T_NATIVE_INT64);
        if (n != counts[std::size_t(k)]) pr.fail("its particle count differs from the manifest's");
        if (H5Lexists(pf.get(), "particles", H5P_DEFAULT) <= 0) pr.fail("group 'particles' is missing");
        Handle g(pr.check_id(H5Gopen2(pf.get(), "particles", H5P_DEFAULT), "group 'particles' is unreadable"));
        Digest pd;
        pd.value(k);
        pd.value(n);
        pd.text(order);
        const auto arrays = read_all(pr, g.get(), n, pd);
        check_digest(pr, pf.get(), pd);
        if (lo < hi) take_rows(pr, arrays, lo - begin, hi - begin);
        else take_rows(pr, arrays, 0, 0);
      }
      begin = end;
    }
    if (begin != h.particles) r.fail("the pieces' particle counts do not add up to 'particles'");
    return c;
  }
  if (h.format_version > kCheckpointFormatVersion)
    r.fail("format_version " + std::to_string(h.format_version) + " without the attribute 'pieces'");
  if (H5Lexists(fid, "particles", H5P_DEFAULT) <= 0) r.fail("group 'particles' is missing");
  Handle parts_group(r.check_id(H5Gopen2(fid, "particles", H5P_DEFAULT), "group 'particles' is unreadable"));
  const auto arrays = read_all(r, parts_group.get(), h.particles, digest);
  // the digest over everything read must match the one written; format 2 on it is required (format 1
  // files were written before it existed)
  if (h.format_version >= 2 || H5Aexists(fid, "content_digest") > 0) check_digest(r, fid, digest);
  take_rows(r, arrays, c.first_row, c.first_row + c.rows);
  return c;
}

std::string checkpoint_file_name(std::int64_t step) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "step_%09lld.h5", static_cast<long long>(step));
  return buf;
}

std::vector<std::pair<std::int64_t, std::filesystem::path>> list_checkpoints(const std::filesystem::path& dir) {
  std::vector<std::pair<std::int64_t, std::filesystem::path>> out;
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return out;
  const std::regex re(R"(step_(\d+)\.h5)");
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    std::smatch m;
    const std::string n = e.path().filename().string();
    if (std::regex_match(n, m, re)) out.emplace_back(std::stoll(m[1]), e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace varsph::io
