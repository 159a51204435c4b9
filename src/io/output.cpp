#include "io/output.hpp"

#include <fcntl.h>
#include <hdf5.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace biofsi {

namespace fs = std::filesystem;

namespace {

// HDF5 prints its error stack to stderr by default, dozens of lines per failure; every call here
// checks its result and reads the stack into one message instead (hdf5_reason).
void silence_hdf5() {
  static const bool silenced = H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr) >= 0;
  (void)silenced;
}

// The reason of the last HDF5 failure, from its error stack (which is then cleared): the system's
// reason where a system call failed (HDF5 records its errno), with the innermost HDF5 message.
std::string hdf5_reason() {
  struct Found {
    std::string innermost;
    int os_errno = 0;
  } found;
  auto walk = [](unsigned depth, const H5E_error2_t* e, void* data) -> herr_t {
    auto& f = *static_cast<Found*>(data);
    const std::string desc = e->desc ? e->desc : "";
    // The description's first clause; the rest repeats errno, a time stamp and buffer addresses.
    if (depth == 0)
      f.innermost = std::string(e->func_name ? e->func_name : "") + ": " +
                    desc.substr(0, desc.find_first_of(":,\n"));
    const size_t at = desc.find("errno = ");
    if (at != std::string::npos && f.os_errno == 0) f.os_errno = std::atoi(desc.c_str() + at + 8);
    return 0;
  };
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, walk, &found);
  H5Eclear2(H5E_DEFAULT);
  const std::string& gist = found.innermost;
  if (found.os_errno != 0)
    return std::string(std::strerror(found.os_errno)) + " (HDF5: " + gist + ")";
  return gist.empty() ? "HDF5 gave no reason" : "HDF5: " + gist;
}

[[noreturn]] void hdf5_failed(const std::string& path, const std::string& what) {
  throw OutputError(path + ": " + what + ": " + hdf5_reason());
}

[[noreturn]] void system_failed(const std::string& path, const std::string& what, int error) {
  throw OutputError(path + ": " + what + ": " + std::strerror(error));
}

// Closes an HDF5 handle on scope exit, so an error path leaks nothing and leaves no open file.
class H5Handle {
 public:
  H5Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~H5Handle() {
    if (id_ >= 0) close_(id_);
  }
  H5Handle(const H5Handle&) = delete;
  H5Handle& operator=(const H5Handle&) = delete;
  hid_t get() const { return id_; }
  bool ok() const { return id_ >= 0; }
  // Close now and report failure (a failed close of a file can mean unwritten data).
  bool close() {
    const herr_t rc = id_ >= 0 ? close_(id_) : 0;
    id_ = -1;
    return rc >= 0;
  }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

void write_dataset(hid_t file, const std::string& path, const std::string& name, hid_t file_type,
                   hid_t mem_type, const std::vector<hsize_t>& dims, const void* data) {
  const std::string what = "cannot write dataset '/" + name + "'";
  H5Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose);
  if (!space.ok()) hdf5_failed(path, what);
  H5Handle set(H5Dcreate2(file, ("/" + name).c_str(), file_type, space.get(), H5P_DEFAULT,
                          H5P_DEFAULT, H5P_DEFAULT),
               H5Dclose);
  if (!set.ok()) hdf5_failed(path, what);
  // An empty dataset has nothing to transfer and a null buffer is then legitimate.
  if (data && H5Dwrite(set.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    hdf5_failed(path, what);
  if (!set.close()) hdf5_failed(path, what);
}

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// Shortest text that reads back to the same double, so the index's times are exact.
std::string exact(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

const char* attribute_type(int n_components) {
  switch (n_components) {
    case 1:
      return "Scalar";
    case 3:
      return "Vector";
    case 6:
      return "Tensor6";
    case 9:
      return "Tensor";
    default:
      return "Matrix";
  }
}

// Writes all of `text` to the open descriptor; false with errno set if the system refuses.
bool write_all(int fd, const std::string& text) {
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<size_t>(n);
  }
  return true;
}

// Moves the written temporary file onto `path`; removes it if that fails.
void rename_into_place(const std::string& tmp, const std::string& path) {
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int error = errno;
    std::error_code ec;
    fs::remove(tmp, ec);
    system_failed(path, "cannot rename " + tmp + " to it", error);
  }
}

// Creates `path` as an HDF5 file through a temporary name: `fill` writes the datasets into the open
// temporary file (messages name `path`), which is renamed only once closed, so a reader never sees
// a partial file.
template <class Fill>
void write_h5_atomically(const std::string& path, const Fill& fill) {
  silence_hdf5();
  const std::string tmp = path + ".tmp";
  try {
    H5Handle file(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
    if (!file.ok()) hdf5_failed(path, "cannot create the HDF5 file");
    fill(file.get(), path);
    // Data still in HDF5's cache reach the disk here: a full disk can show only now.
    if (!file.close()) hdf5_failed(path, "cannot write the HDF5 file");
    rename_into_place(tmp, path);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
}

}  // namespace

void write_text_file(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) system_failed(path, "cannot create " + tmp, errno);
  const bool written = write_all(fd, text);
  const int write_error = errno;
  // close() can report a failed write that the system deferred (NFS, quotas).
  const bool closed = ::close(fd) == 0;
  const int error = !written ? write_error : errno;
  if (!written || !closed) {
    std::error_code ec;
    fs::remove(tmp, ec);
    system_failed(path, "cannot write", error);
  }
  rename_into_place(tmp, path);
}

TextLog::TextLog(const std::string& path)
    : path_(path), fd_(::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644)) {
  if (fd_ < 0) system_failed(path, "cannot create", errno);
}

TextLog::~TextLog() {
  if (fd_ >= 0) ::close(fd_);
}

TextLog::TextLog(TextLog&& other) noexcept : path_(std::move(other.path_)), fd_(other.fd_) {
  other.fd_ = -1;
}

TextLog& TextLog::operator=(TextLog&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    path_ = std::move(other.path_);
    fd_ = other.fd_;
    other.fd_ = -1;
  }
  return *this;
}

void TextLog::append(const std::string& text) {
  if (!write_all(fd_, text)) system_failed(path_, "cannot write", errno);
}

XdmfWriter::XdmfWriter(const std::string& directory, const std::string& basename, bool overwrite)
    : directory_(directory), basename_(basename) {
  if (basename.empty() || basename.find('/') != std::string::npos)
    throw std::invalid_argument("output basename '" + basename + "' must be a plain file name");
  std::error_code ec;
  fs::create_directories(directory_, ec);
  if (ec) system_failed(directory_, "cannot create the output directory", ec.value());
  index_path_ = (fs::path(directory_) / (basename_ + ".xdmf")).string();
  if (fs::exists(index_path_) && !overwrite)
    throw std::invalid_argument(index_path_ +
                                " already exists; pass --overwrite to replace it or choose "
                                "another --out directory");
  // Overwriting replaces the whole series: step files of an earlier (longer) run would otherwise
  // stay beside the new index and be mistaken for this run's.
  if (overwrite && fs::is_directory(directory_))
    for (const auto& e : fs::directory_iterator(directory_)) {
      const std::string name = e.path().filename().string();
      if (name.size() == basename_.size() + 10 && name.rfind(basename_ + "_", 0) == 0 &&
          e.path().extension() == ".h5" &&
          std::all_of(name.begin() + basename_.size() + 1, name.end() - 3,
                      [](char c) { return c >= '0' && c <= '9'; })) {
        std::error_code ec;
        fs::remove(e.path(), ec);
      }
    }
  // An empty index at once: a reader never pairs the old index with this run's step files, and
  // a second writer aimed at the same place is refused from the start.
  write_index();
}

void XdmfWriter::write(int step, double time, const Mesh& mesh,
                       const std::vector<OutputField>& fields) {
  if (step < 0)
    throw std::invalid_argument("output step must be >= 0, got " + std::to_string(step));
  const int n_nodes = mesh.n_nodes(), n_elements = mesh.n_elements();
  for (const auto& f : fields) {
    if (f.name.empty() || f.name.find_first_of("/.") != std::string::npos ||
        f.name == "coordinates" || f.name == "connectivity" || f.name == "block")
      throw std::invalid_argument("output field name '" + f.name +
                                  "' is empty, contains '/' or '.', or is reserved");
    const size_t n = static_cast<size_t>(f.cell_centered ? n_elements : n_nodes);
    if (f.n_components < 1 || f.values.size() != n * static_cast<size_t>(f.n_components))
      throw std::invalid_argument("output field '" + f.name + "' has " +
                                  std::to_string(f.values.size()) + " values, expected " +
                                  std::to_string(n) + " x " + std::to_string(f.n_components));
  }
  for (size_t a = 0; a < fields.size(); ++a)
    for (size_t b = a + 1; b < fields.size(); ++b)
      if (fields[a].name == fields[b].name)
        throw std::invalid_argument("output field '" + fields[a].name + "' given twice");

  char number[16];
  std::snprintf(number, sizeof number, "%06d", step);
  const std::string h5 = basename_ + "_" + number + ".h5";
  const std::string path = (fs::path(directory_) / h5).string();
  write_h5_atomically(path, [&](hid_t file, const std::string& tmp) {
    const hsize_t nn = static_cast<hsize_t>(n_nodes), ne = static_cast<hsize_t>(n_elements);
    std::vector<double> xyz;
    xyz.reserve(3 * mesh.x.size());
    for (const auto& p : mesh.x) xyz.insert(xyz.end(), p.begin(), p.end());
    write_dataset(file, tmp, "coordinates", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {nn, 3},
                  xyz.empty() ? nullptr : xyz.data());
    std::vector<int> conn;
    conn.reserve(8 * mesh.conn.size());
    for (const auto& c : mesh.conn) conn.insert(conn.end(), c.begin(), c.end());
    write_dataset(file, tmp, "connectivity", H5T_STD_I32LE, H5T_NATIVE_INT, {ne, 8},
                  conn.empty() ? nullptr : conn.data());
    std::vector<int> block(mesh.element_block);
    block.resize(mesh.conn.size(), 0);
    write_dataset(file, tmp, "block", H5T_STD_I32LE, H5T_NATIVE_INT, {ne},
                  block.empty() ? nullptr : block.data());
    for (const auto& f : fields)
      write_dataset(file, tmp, f.name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
                    {f.cell_centered ? ne : nn, static_cast<hsize_t>(f.n_components)},
                    f.values.empty() ? nullptr : f.values.data());
  });

  Entry entry{step, time, h5, n_nodes, n_elements, {}};
  for (const auto& f : fields) entry.meta.push_back({f.name, f.n_components, f.cell_centered, {}});
  // Writing a step again (a restarted run) replaces it rather than listing it twice.
  auto same = std::find_if(entries_.begin(), entries_.end(),
                           [&](const Entry& e) { return e.step == step; });
  if (same != entries_.end())
    *same = std::move(entry);
  else
    entries_.push_back(std::move(entry));
  write_index();
}

void XdmfWriter::write_index() const {
  std::ostringstream x;
  x << "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n"
    << "<Xdmf Version=\"3.0\" xmlns:xi=\"http://www.w3.org/2001/XInclude\">\n"
    << "  <Domain>\n"
    << "    <Grid Name=\"" << xml_escape(basename_)
    << "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const auto& e : entries_) {
    const std::string h5 = xml_escape(e.h5);
    auto item = [&](const std::string& dims, const char* type, int precision,
                    const std::string& dataset) {
      std::ostringstream s;
      s << "          <DataItem Dimensions=\"" << dims << "\" NumberType=\"" << type
        << "\" Precision=\"" << precision << "\" Format=\"HDF\">" << h5 << ":/"
        << xml_escape(dataset) << "</DataItem>\n";
      return s.str();
    };
    const std::string ne = std::to_string(e.n_elements), nn = std::to_string(e.n_nodes);
    x << "      <Grid Name=\"step_" << e.step << "\" GridType=\"Uniform\">\n"
      << "        <Time Value=\"" << exact(e.time) << "\"/>\n"
      << "        <Topology TopologyType=\"Hexahedron\" NumberOfElements=\"" << ne << "\">\n"
      << item(ne + " 8", "Int", 4, "connectivity") << "        </Topology>\n"
      << "        <Geometry GeometryType=\"XYZ\">\n"
      << item(nn + " 3", "Float", 8, "coordinates") << "        </Geometry>\n"
      << "        <Attribute Name=\"block\" AttributeType=\"Scalar\" Center=\"Cell\">\n"
      << item(ne, "Int", 4, "block") << "        </Attribute>\n";
    for (const auto& f : e.meta) {
      const std::string n = f.cell_centered ? ne : nn;
      x << "        <Attribute Name=\"" << xml_escape(f.name) << "\" AttributeType=\""
        << attribute_type(f.n_components) << "\" Center=\"" << (f.cell_centered ? "Cell" : "Node")
        << "\">\n"
        << item(n + " " + std::to_string(f.n_components), "Float", 8, f.name)
        << "        </Attribute>\n";
    }
    x << "      </Grid>\n";
  }
  x << "    </Grid>\n  </Domain>\n</Xdmf>\n";
  write_text_file(index_path_, x.str());
}

void write_h5_datasets(const std::string& path,
                       const std::vector<std::pair<std::string, std::vector<double>>>& datasets) {
  write_h5_atomically(path, [&](hid_t file, const std::string& tmp) {
    for (const auto& [name, values] : datasets)
      write_dataset(file, tmp, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
                    {static_cast<hsize_t>(values.size())},
                    values.empty() ? nullptr : values.data());
  });
}

std::vector<double> read_h5_dataset(const std::string& h5_path, const std::string& dataset) {
  silence_hdf5();
  if (!fs::is_regular_file(h5_path)) throw std::runtime_error(h5_path + ": no such file");
  H5Handle file(H5Fopen(h5_path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!file.ok())
    throw std::runtime_error(h5_path + ": cannot open as HDF5 (" + hdf5_reason() + ")");
  const std::string name = dataset.empty() || dataset[0] != '/' ? "/" + dataset : dataset;
  // Check each link on the way so that a missing name is an exception, not an HDF5 error dump.
  for (size_t pos = name.find('/', 1);; pos = name.find('/', pos + 1)) {
    const std::string prefix = name.substr(0, pos);
    if (prefix.size() <= 1 || H5Lexists(file.get(), prefix.c_str(), H5P_DEFAULT) <= 0)
      throw std::runtime_error(h5_path + ": no dataset '" + name + "'");
    if (pos == std::string::npos) break;
  }
  H5Handle set(H5Dopen2(file.get(), name.c_str(), H5P_DEFAULT), H5Dclose);
  if (!set.ok()) throw std::runtime_error(h5_path + ": '" + name + "' is not a dataset");
  H5Handle space(H5Dget_space(set.get()), H5Sclose);
  const hssize_t n = space.ok() ? H5Sget_simple_extent_npoints(space.get()) : -1;
  if (n < 0) throw std::runtime_error(h5_path + ": cannot read the shape of '" + name + "'");
  std::vector<double> out(static_cast<size_t>(n));
  if (n > 0 && H5Dread(set.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    throw std::runtime_error(h5_path + ": cannot read '" + name + "' as numbers");
  return out;
}

}  // namespace biofsi
