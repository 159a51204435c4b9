#include "mesh/gmsh.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <set>
#include <sstream>

namespace biofsi {

namespace {

// The fewest bytes a node takes in $Nodes: its tag ("t\n") and its coordinates ("x y z\n").
constexpr long long kNodeBytes = 8;

// Line-oriented reader that knows where it is, for messages, and how much of the file is left, so
// that a count is checked against what the file can hold before anything is allocated for it.
class MshReader {
 public:
  explicit MshReader(const std::string& path) : path_(path) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status))
      throw MeshFileError(path + ": cannot open the mesh file: no such file");
    // A device or pipe (/dev/zero) could be read forever.
    if (!std::filesystem::is_regular_file(status))
      throw MeshFileError(path + ": cannot open the mesh file: not a regular file");
    size_ = static_cast<long long>(std::filesystem::file_size(path, ec));
    in_.open(path, std::ios::binary);
    if (!in_ || ec)
      throw MeshFileError(path + ": cannot open the mesh file: " + std::strerror(errno));
  }

  bool next_line(std::string& line) {
    if (!std::getline(in_, line)) return false;
    ++line_number_;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
  }

  std::istringstream record(const char* what) {
    std::string line;
    if (!next_line(line)) fail(std::string("the file ends inside ") + what);
    return std::istringstream(line);
  }

  template <class... T>
  void read(std::istringstream& s, const char* what, T&... values) {
    if (!(s >> ... >> values)) fail(std::string("cannot read ") + what);
  }

  void expect_end(const std::string& section) {
    std::string line;
    if (!next_line(line))
      fail("the file ends inside $" + section + ", expected '$End" + section + "'");
    if (line != "$End" + section) fail("expected '$End" + section + "', got '" + line + "'");
  }

  [[noreturn]] void fail(const std::string& why) const {
    throw MeshFileError(path_ + ":" + std::to_string(line_number_) + ": " + why);
  }

  // A count read from the file, before anything is allocated for it: not negative, and not more
  // records of at least `record_bytes` each than the rest of the file holds.
  void check_count(long long n, const char* what, long long record_bytes) {
    if (n < 0) fail("negative number of " + std::string(what) + " (" + std::to_string(n) + ")");
    const long long left = std::max(0LL, size_ - static_cast<long long>(in_.tellg()));
    if (n > left / record_bytes)
      fail(std::to_string(n) + " " + what + " announced, but the rest of the file (" +
           std::to_string(left) + " bytes) holds at most " + std::to_string(left / record_bytes));
  }

  // A count within one line `s` of records of at least `record_bytes` characters each.
  void check_count_in_line(long long n, const char* what, const std::istringstream& s,
                           long long record_bytes) {
    if (n < 0) fail("negative number of " + std::string(what) + " (" + std::to_string(n) + ")");
    if (n > static_cast<long long>(s.str().size()) / record_bytes)
      fail(std::to_string(n) + " " + what + " announced in a line of " +
           std::to_string(s.str().size()) + " characters");
  }

 private:
  std::string path_;
  std::ifstream in_;
  long long size_ = 0;
  int line_number_ = 0;
};

struct RawMesh {
  std::map<std::pair<int, int>, std::string> physical_names;         // (dim, tag) -> name
  std::map<std::pair<int, int>, std::vector<int>> entity_physicals;  // (dim, entity) -> tags
  std::map<long long, Point> nodes;
  struct Cell {
    int dim, entity;
    long long tag;
    std::vector<long long> nodes;
  };
  std::vector<Cell> hexes, quads, lower;  // lower: points (type 15) and lines (type 1)
};

void read_mesh_format(MshReader& r) {
  auto s = r.record("$MeshFormat");
  double version = 0;
  int file_type = -1, data_size = 0;
  r.read(s, "the format line (version file-type data-size)", version, file_type, data_size);
  if (version < 4.1 || version >= 5.0 || file_type != 0)
    r.fail("unsupported mesh format " + std::to_string(version) + (file_type ? " binary" : "") +
           ", expected MSH 4.1 ASCII (gmsh -format msh41)");
  r.expect_end("MeshFormat");
}

void read_physical_names(MshReader& r, RawMesh& m) {
  auto s = r.record("$PhysicalNames");
  long long n = 0;
  r.read(s, "the number of physical names", n);
  r.check_count(n, "physical names", 7);  // d t "name"
  for (long long i = 0; i < n; ++i) {
    auto rec = r.record("$PhysicalNames");
    int dim = 0, tag = 0;
    r.read(rec, "a physical name (dim tag \"name\")", dim, tag);
    std::string rest;
    std::getline(rec, rest);
    const auto a = rest.find('"'), b = rest.rfind('"');
    if (a == std::string::npos || b == a) r.fail("physical name without quotes");
    m.physical_names[{dim, tag}] = rest.substr(a + 1, b - a - 1);
  }
  r.expect_end("PhysicalNames");
}

void read_entities(MshReader& r, RawMesh& m) {
  auto s = r.record("$Entities");
  long long counts[4] = {0, 0, 0, 0};
  r.read(s, "the entity counts", counts[0], counts[1], counts[2], counts[3]);
  for (int dim = 0; dim < 4; ++dim) r.check_count(counts[dim], "entities", 2 * (dim == 0 ? 5 : 8));
  for (int dim = 0; dim < 4; ++dim)
    for (long long i = 0; i < counts[dim]; ++i) {
      auto rec = r.record("$Entities");
      int tag = 0;
      double box[6];
      const int n_coords = dim == 0 ? 3 : 6;
      r.read(rec, "an entity tag", tag);
      for (int c = 0; c < n_coords; ++c) r.read(rec, "an entity's bounding box", box[c]);
      long long n_physicals = 0;
      r.read(rec, "an entity's number of physical tags", n_physicals);
      r.check_count_in_line(n_physicals, "physical tags", rec, 2);
      std::vector<int> tags(n_physicals);
      for (int& t : tags) r.read(rec, "a physical tag", t);
      m.entity_physicals[{dim, tag}] = tags;
    }
  r.expect_end("Entities");
}

void read_nodes(MshReader& r, RawMesh& m) {
  auto s = r.record("$Nodes");
  long long n_blocks = 0, n_nodes = 0, min_tag = 0, max_tag = 0;
  r.read(s, "the node header", n_blocks, n_nodes, min_tag, max_tag);
  r.check_count(n_blocks, "node blocks", 8);
  r.check_count(n_nodes, "nodes", kNodeBytes);
  const std::string memory = memory_shortfall(n_nodes);
  if (!memory.empty()) r.fail("the mesh is too large: " + memory);
  for (long long b = 0; b < n_blocks; ++b) {
    auto head = r.record("$Nodes");
    int dim = 0, entity = 0, parametric = 0;
    long long n = 0;
    r.read(head, "a node block header", dim, entity, parametric, n);
    if (parametric) r.fail("parametric node coordinates are not supported; save without them");
    r.check_count(n, "nodes", kNodeBytes);
    std::vector<long long> tags(n);
    for (auto& t : tags) {
      auto rec = r.record("$Nodes");
      r.read(rec, "a node tag", t);
    }
    for (auto t : tags) {
      auto rec = r.record("$Nodes");
      Point p;
      r.read(rec, "node coordinates", p[0], p[1], p[2]);
      if (!m.nodes.emplace(t, p).second) r.fail("node " + std::to_string(t) + " is defined twice");
    }
  }
  if (static_cast<long long>(m.nodes.size()) != n_nodes)
    r.fail("the header announces " + std::to_string(n_nodes) + " nodes, the blocks hold " +
           std::to_string(m.nodes.size()));
  r.expect_end("Nodes");
}

int nodes_per_element(int type) {
  switch (type) {
    case 15:
      return 1;  // point
    case 1:
      return 2;  // line
    case 2:
      return 3;  // triangle
    case 3:
      return 4;  // quadrilateral
    case 4:
      return 4;  // tetrahedron
    case 5:
      return 8;  // hexahedron
    case 6:
      return 6;  // prism
    case 7:
      return 5;  // pyramid
    default:
      return -1;
  }
}

void read_elements(MshReader& r, RawMesh& m) {
  auto s = r.record("$Elements");
  long long n_blocks = 0, n_elements = 0, min_tag = 0, max_tag = 0;
  r.read(s, "the element header", n_blocks, n_elements, min_tag, max_tag);
  r.check_count(n_blocks, "element blocks", 8);
  r.check_count(n_elements, "elements", 4);  // the shortest: a point, "t n"
  for (long long b = 0; b < n_blocks; ++b) {
    auto head = r.record("$Elements");
    int dim = 0, entity = 0, type = 0;
    long long n = 0;
    r.read(head, "an element block header", dim, entity, type, n);
    const int nn = nodes_per_element(type);
    // Each dimension has the one element type the mesh is built from.
    const int expected_type[4] = {15, 1, 3, 5};
    if (dim < 0 || dim > 3 || type != expected_type[dim])
      r.fail("element type " + std::to_string(type) + " in a " + std::to_string(dim) +
             "-D entity; expected hexahedra (5), quadrilaterals (3), lines (1) and points (15) "
             "only: recombine and extrude with Recombine");
    r.check_count(n, "elements", 2 * (nn + 1));
    for (long long i = 0; i < n; ++i) {
      auto rec = r.record("$Elements");
      long long tag = 0;
      r.read(rec, "an element tag", tag);
      RawMesh::Cell cell{dim, entity, tag, std::vector<long long>(nn)};
      for (auto& v : cell.nodes) {
        r.read(rec, "an element's node tags", v);
        if (!m.nodes.count(v))
          r.fail("element " + std::to_string(tag) + " uses node " + std::to_string(v) +
                 ", which $Nodes does not define");
      }
      (dim == 3 ? m.hexes : dim == 2 ? m.quads : m.lower).push_back(std::move(cell));
    }
  }
  r.expect_end("Elements");
}

void skip_section(MshReader& r, const std::string& name) {
  std::string line;
  while (r.next_line(line))
    if (line == "$End" + name) return;
  r.fail("section $" + name + " is not closed");
}

using FaceKey = std::array<int, 4>;
FaceKey face_key(std::array<int, 4> nodes) {
  std::sort(nodes.begin(), nodes.end());
  return nodes;
}

// Blocks from the physical groups of dimension `dim`, in tag order.
std::map<int, int> blocks_from_physicals(const RawMesh& raw, int dim, Mesh& m) {
  std::map<int, int> block_of_physical;
  for (const auto& [key, name] : raw.physical_names)
    if (key.first == dim) {
      block_of_physical[key.second] = static_cast<int>(m.block_names.size());
      m.block_names.push_back(name);
    }
  return block_of_physical;
}

std::vector<std::string> physical_names_of(const RawMesh& raw, int dim, int entity) {
  std::vector<std::string> names;
  auto phys = raw.entity_physicals.find({dim, entity});
  if (phys == raw.entity_physicals.end()) return names;
  for (int t : phys->second) {
    auto it = raw.physical_names.find({dim, t});
    names.push_back(it != raw.physical_names.end() ? it->second : std::to_string(t));
  }
  return names;
}

// A boundary polygon of the final hex mesh: the named face with these (local) nodes.
struct NamedFace {
  std::vector<std::string> names;
  std::array<int, 4> nodes;
};

// Hexahedra and named faces in local numbering, from a 3-D file or from a 2-D one extruded.
struct Cells {
  std::vector<std::array<int, 8>> hexes;
  std::vector<long long> tag;  // the file's element tag (of the quadrilateral, when extruded)
  std::vector<int> block;
  std::vector<NamedFace> faces;
  std::map<std::string, std::set<int>> node_sets;  // from curves and points (3-D) or points (2-D)
};

int block_of_entity(const RawMesh& raw, const std::map<int, int>& block_of_physical, int dim,
                    int entity, const std::string& path) {
  auto phys = raw.entity_physicals.find({dim, entity});
  std::vector<int> blocks;
  if (phys != raw.entity_physicals.end())
    for (int t : phys->second)
      if (block_of_physical.count(t)) blocks.push_back(block_of_physical.at(t));
  if (blocks.size() != 1)
    throw MeshFileError(path + ": " + (dim == 3 ? "volume" : "surface") + " entity " +
                        std::to_string(entity) + " belongs to " + std::to_string(blocks.size()) +
                        " physical groups, expected exactly one (it becomes an element block)");
  return blocks[0];
}

Cells cells_from_hexahedra(const std::string& path, const RawMesh& raw, Mesh& m,
                           std::map<long long, int>& local) {
  auto block_of_physical = blocks_from_physicals(raw, 3, m);
  if (m.block_names.empty())
    throw MeshFileError(path + ": no physical volume; name the volumes with Physical Volume(...)");
  std::set<long long> used;
  for (const auto& h : raw.hexes) used.insert(h.nodes.begin(), h.nodes.end());
  for (long long tag : used) {
    local[tag] = static_cast<int>(m.x.size());
    m.x.push_back(raw.nodes.at(tag));
  }
  Cells c;
  for (const auto& h : raw.hexes) {
    std::array<int, 8> v;
    for (int a = 0; a < 8; ++a) v[a] = local.at(h.nodes[a]);
    c.hexes.push_back(v);
    c.tag.push_back(h.tag);
    c.block.push_back(block_of_entity(raw, block_of_physical, 3, h.entity, path));
  }
  for (const auto& q : raw.quads) {
    NamedFace f{physical_names_of(raw, 2, q.entity), {}};
    if (f.names.empty()) continue;
    for (int k = 0; k < 4; ++k) {
      auto it = local.find(q.nodes[k]);
      if (it == local.end())
        throw MeshFileError(path + ": a quadrilateral of surface '" + f.names[0] +
                            "' uses a node of no hexahedron");
      f.nodes[k] = it->second;
    }
    c.faces.push_back(f);
  }
  for (const auto& cell : raw.lower)
    for (const auto& name : physical_names_of(raw, cell.dim, cell.entity))
      for (long long tag : cell.nodes)
        if (local.count(tag)) c.node_sets[name].insert(local.at(tag));
  return c;
}

// One layer of hexahedra over the quadrilaterals: node n at z = 0 and n + n2 at z = thickness.
// Physical curves become the extruded side faces; "front" (z = 0) and "back" are added.
Cells cells_from_extruded_quads(const std::string& path, const RawMesh& raw, double thickness,
                                Mesh& m, std::map<long long, int>& local) {
  auto block_of_physical = blocks_from_physicals(raw, 2, m);
  if (m.block_names.empty())
    throw MeshFileError(path +
                        ": no hexahedra and no physical surface; name the surfaces with "
                        "Physical Surface(...) (or mesh the volume with hexahedra)");
  if (!(thickness > 0))
    throw MeshFileError(path +
                        ": a 2-D quadrilateral mesh is extruded into one hex layer and needs "
                        "a thickness > 0; got " +
                        std::to_string(thickness));
  std::set<long long> used;
  for (const auto& q : raw.quads)
    if (!physical_names_of(raw, 2, q.entity).empty()) used.insert(q.nodes.begin(), q.nodes.end());
  for (long long tag : used) {
    local[tag] = static_cast<int>(m.x.size());
    m.x.push_back(raw.nodes.at(tag));
  }
  const int n2 = static_cast<int>(m.x.size());
  for (int n = 0; n < n2; ++n) {
    if (std::abs(m.x[n][2]) > 1e-12 * (1 + std::abs(m.x[n][0]) + std::abs(m.x[n][1])))
      throw MeshFileError(path + ": a 2-D mesh must lie in the plane z = 0; a node has z = " +
                          std::to_string(m.x[n][2]));
    m.x[n][2] = 0;
    m.x.push_back({m.x[n][0], m.x[n][1], thickness});
  }
  Cells c;
  for (const auto& q : raw.quads) {
    if (physical_names_of(raw, 2, q.entity).empty()) continue;
    std::array<int, 8> v;
    for (int k = 0; k < 4; ++k) {
      v[k] = local.at(q.nodes[k]);
      v[k + 4] = v[k] + n2;
    }
    c.hexes.push_back(v);
    c.tag.push_back(q.tag);
    c.block.push_back(block_of_entity(raw, block_of_physical, 2, q.entity, path));
    c.faces.push_back({{"front"}, {v[0], v[1], v[2], v[3]}});
    c.faces.push_back({{"back"}, {v[4], v[5], v[6], v[7]}});
  }
  for (const auto& cell : raw.lower) {
    const auto names = physical_names_of(raw, cell.dim, cell.entity);
    if (names.empty()) continue;
    std::vector<int> v;
    for (long long tag : cell.nodes) {
      auto it = local.find(tag);
      if (it == local.end())
        throw MeshFileError(path + ": physical group '" + names[0] + "' uses a node of no " +
                            "quadrilateral of a physical surface");
      v.push_back(it->second);
    }
    if (cell.dim == 1)
      c.faces.push_back({names, {v[0], v[1], v[1] + n2, v[0] + n2}});
    else
      for (const auto& name : names) c.node_sets[name].insert({v[0], v[0] + n2});
  }
  return c;
}

// The hexahedra into the mesh, each checked at its 8 corners: a consistently mirrored one (every
// corner left-handed) is re-oriented and counted; an inverted, folded or degenerate one stops the
// read, naming the element, its block and the worst corner's scaled Jacobian.
int add_checked_hexahedra(const std::string& path, const Cells& cells, Mesh& m) {
  int mirrored = 0;
  for (size_t e = 0; e < cells.hexes.size(); ++e) {
    auto c = cells.hexes[e];
    const ElementCheck check = check_element(m, c);
    if (check.shape == ElementShape::Mirrored) {
      c = reorient(c);
      ++mirrored;
    } else if (check.shape != ElementShape::Valid) {
      std::ostringstream msg;
      msg << path << ": element " << cells.tag[e] << " of block '" << m.block_names[cells.block[e]]
          << "' is " << shape_name(check.shape) << ": scaled Jacobian " << check.value
          << " at its corner " << check.corner << " (of 0-7 in VTK order); expected above "
          << kDegenerateJacobian << " at all 8 corners (or below -" << kDegenerateJacobian
          << " at all 8: a mirrored element, re-oriented)";
      throw MeshFileError(msg.str());
    }
    m.conn.push_back(c);
    m.element_block.push_back(cells.block[e]);
  }
  return mirrored;
}

Mesh build_mesh(const std::string& path, const RawMesh& raw, double thickness, int* reoriented) {
  Mesh m;
  std::map<long long, int> local;
  Cells cells = raw.hexes.empty() ? cells_from_extruded_quads(path, raw, thickness, m, local)
                                  : cells_from_hexahedra(path, raw, m, local);
  const int mirrored = add_checked_hexahedra(path, cells, m);
  if (reoriented) *reoriented = mirrored;

  std::map<FaceKey, std::vector<BoundaryFace>> faces;
  for (int e = 0; e < m.n_elements(); ++e)
    for (int f = 0; f < 6; ++f) {
      std::array<int, 4> fn;
      for (int k = 0; k < 4; ++k) fn[k] = m.conn[e][hex8_face_nodes[f][k]];
      faces[face_key(fn)].push_back({e, f});
    }
  for (const auto& nf : cells.faces) {
    auto it = faces.find(face_key(nf.nodes));
    if (it == faces.end())
      throw MeshFileError(path + ": a face of boundary '" + nf.names[0] +
                          "' is not a face of any hexahedron");
    for (const auto& name : nf.names) {
      for (const auto& bf : it->second) m.face_sets[name].push_back(bf);
      cells.node_sets[name].insert(nf.nodes.begin(), nf.nodes.end());
    }
  }
  for (const auto& [name, nodes] : cells.node_sets)
    m.node_sets[name] = std::vector<int>(nodes.begin(), nodes.end());

  m.global_node_id.resize(m.x.size());
  std::iota(m.global_node_id.begin(), m.global_node_id.end(), 0LL);
  m.n_owned_nodes = m.n_nodes();
  return m;
}

}  // namespace

Mesh read_gmsh(const std::string& path, double thickness, int* reoriented) {
  MshReader r(path);
  RawMesh raw;
  bool have_format = false, have_entities = false, have_nodes = false, have_elements = false;
  std::string line;
  while (r.next_line(line)) {
    if (line.empty()) continue;
    if (line == "$MeshFormat") {
      read_mesh_format(r);
      have_format = true;
    } else if (line == "$PhysicalNames") {
      read_physical_names(r, raw);
    } else if (line == "$Entities") {
      read_entities(r, raw);
      have_entities = true;
    } else if (line == "$Nodes") {
      if (!have_format) r.fail("$Nodes before $MeshFormat");
      read_nodes(r, raw);
      have_nodes = true;
    } else if (line == "$Elements") {
      if (!have_nodes) r.fail("$Elements before $Nodes");
      read_elements(r, raw);
      have_elements = true;
    } else if (line[0] == '$') {
      skip_section(r, line.substr(1));
    } else {
      r.fail("unexpected line '" + line + "' outside a section");
    }
  }
  if (!have_format || !have_entities || !have_nodes || !have_elements)
    throw MeshFileError(path +
                        ": missing section(s); expected $MeshFormat, $Entities, $Nodes and "
                        "$Elements of a MSH 4.1 ASCII file");
  return build_mesh(path, raw, thickness, reoriented);
}

Mesh mesh_geo_with_gmsh(const std::string& geo_path,
                        const std::vector<std::pair<std::string, double>>& parameters,
                        double thickness, int* reoriented) {
  namespace fs = std::filesystem;
  if (!fs::is_regular_file(geo_path)) throw MeshFileError(geo_path + ": cannot open the .geo file");
  const fs::path dir = fs::temp_directory_path();
  const std::string stem =
      "biofsi_gmsh_" + std::to_string(getpid()) + "_" + fs::path(geo_path).stem().string();
  const std::string msh = (dir / (stem + ".msh")).string(), log = (dir / (stem + ".log")).string();
  std::vector<std::string> args = {"gmsh", thickness > 0 ? "-2" : "-3", "-format", "msh41", "-v",
                                   "2"};
  for (const auto& [name, value] : parameters) {
    std::ostringstream v;
    v.precision(17);
    v << value;
    args.insert(args.end(), {"-setnumber", name, v.str()});
  }
  args.insert(args.end(), {geo_path, "-o", msh});
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  // gmsh's messages go to a log file, quoted in the error if it fails.
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, "gmsh", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0)
    throw MeshFileError(geo_path + ": cannot run gmsh (" + std::strerror(spawned) +
                        "); install Debian's gmsh (scripts/setup does)");
  int status = 0;
  waitpid(pid, &status, 0);
  std::ifstream log_in(log);
  std::string messages((std::istreambuf_iterator<char>(log_in)), std::istreambuf_iterator<char>());
  fs::remove(log);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !fs::exists(msh)) {
    fs::remove(msh);
    throw MeshFileError(geo_path + ": gmsh failed (" +
                        (WIFEXITED(status) ? "exit status " + std::to_string(WEXITSTATUS(status))
                                           : std::string("killed by a signal")) +
                        "): " + messages);
  }
  try {
    Mesh m = read_gmsh(msh, thickness, reoriented);
    fs::remove(msh);
    return m;
  } catch (...) {
    fs::remove(msh);
    throw;
  }
}

Mesh submesh(const Mesh& mesh, const std::vector<std::string>& blocks,
             std::vector<int>* parent_node) {
  Mesh m;
  std::vector<int> new_block(mesh.block_names.size(), -1);
  for (size_t b = 0; b < mesh.block_names.size(); ++b)
    if (std::find(blocks.begin(), blocks.end(), mesh.block_names[b]) != blocks.end()) {
      new_block[b] = static_cast<int>(m.block_names.size());
      m.block_names.push_back(mesh.block_names[b]);
    }
  for (const auto& name : blocks)
    if (mesh.block_index(name) < 0)
      throw std::invalid_argument("submesh: the mesh has no block '" + name + "'");

  std::vector<int> new_element(mesh.n_elements(), -1), new_node(mesh.n_nodes(), -1);
  for (int e = 0; e < mesh.n_elements(); ++e)
    if (new_block[mesh.element_block[e]] >= 0) {
      new_element[e] = m.n_elements();
      m.conn.push_back(mesh.conn[e]);
      m.element_block.push_back(new_block[mesh.element_block[e]]);
      for (int n : mesh.conn[e]) new_node[n] = 0;
    }
  std::vector<int> parent;
  for (int n = 0; n < mesh.n_nodes(); ++n)
    if (new_node[n] == 0) {
      new_node[n] = static_cast<int>(m.x.size());
      m.x.push_back(mesh.x[n]);
      m.global_node_id.push_back(mesh.global_node_id.empty() ? n : mesh.global_node_id[n]);
      parent.push_back(n);
    }
  for (auto& c : m.conn)
    for (int& n : c) n = new_node[n];
  for (const auto& [name, faces] : mesh.face_sets) {
    std::vector<BoundaryFace> kept;
    for (const auto& f : faces)
      if (new_element[f.element] >= 0) kept.push_back({new_element[f.element], f.local_face});
    if (!kept.empty()) m.face_sets[name] = kept;
  }
  for (const auto& [name, nodes] : mesh.node_sets) {
    std::vector<int> kept;
    for (int n : nodes)
      if (new_node[n] >= 0) kept.push_back(new_node[n]);
    if (!kept.empty()) m.node_sets[name] = kept;
  }
  m.n_owned_nodes = m.n_nodes();
  if (parent_node) *parent_node = parent;
  return m;
}

}  // namespace biofsi
