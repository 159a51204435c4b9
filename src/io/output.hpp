// Results as HDF5 (one file per written step) with an XDMF index that ParaView opens as a time
// series. Every file is written to a temporary name and renamed, so a killed run never leaves a
// corrupt file behind; the XDMF index always lists only complete steps. Every write is checked:
// a failure throws OutputError naming the file and the system's reason. HDF5 prints nothing of
// its own: its error stack is read into that message instead.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "mesh/mesh.hpp"

namespace biofsi {

// A file of the results could not be written: "<file>: <what failed>: <reason>", the reason the
// system's (strerror: "No space left on device", "Permission denied") where it gave one.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct OutputField {
  std::string name;
  int n_components = 1;
  bool cell_centered = false;  // false: one value tuple per node; true: per element
  std::vector<double> values;  // interleaved components
};

class XdmfWriter {
 public:
  // Files go to directory/<basename>_<step>.h5 and directory/<basename>.xdmf. The directory is
  // created if missing (OutputError if it cannot be). An existing index of the same name is
  // overwritten only if `overwrite`; otherwise the constructor throws std::invalid_argument naming
  // the file. Overwriting also removes the step files <basename>_NNNNNN.h5 of the earlier series.
  XdmfWriter(const std::string& directory, const std::string& basename, bool overwrite);

  // Writes mesh coordinates, connectivity, block id (cell field "block") and the fields at `time`.
  void write(int step, double time, const Mesh& mesh, const std::vector<OutputField>& fields);

  const std::string& index_path() const { return index_path_; }

 private:
  std::string directory_, basename_, index_path_;
  struct Entry {
    int step;
    double time;
    std::string h5;
    int n_nodes, n_elements;
    std::vector<OutputField> meta;  // values left empty
  };
  std::vector<Entry> entries_;
  void write_index() const;
};

// Writes `text` to `path` through a temporary file (summaries, tables); OutputError on failure.
void write_text_file(const std::string& path, const std::string& text);

// A text file written a piece at a time, each piece handed to the system at once so that the
// rows written so far survive the run being stopped (series.csv); OutputError on failure.
class TextLog {
 public:
  TextLog() = default;
  explicit TextLog(const std::string& path);  // created, or truncated
  ~TextLog();
  TextLog(TextLog&& other) noexcept;
  TextLog& operator=(TextLog&& other) noexcept;
  bool is_open() const { return fd_ >= 0; }
  void append(const std::string& text);

 private:
  std::string path_;
  int fd_ = -1;
};

// Writes named one-dimensional double datasets to `path` through a temporary file (checkpoints).
void write_h5_datasets(const std::string& path,
                       const std::vector<std::pair<std::string, std::vector<double>>>& datasets);

// Reads one dataset of a written step back (tests, restart, post-processing).
std::vector<double> read_h5_dataset(const std::string& h5_path, const std::string& dataset);

}  // namespace biofsi
