// Outputs that appear whole or not at all: a file written to a temporary name and renamed on
// Commit(), and a staging folder whose entries move into the destination on Commit().
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

namespace squint::io {

class AtomicFile {
 public:
  // Throws squint::Error when the temporary file cannot be created.
  explicit AtomicFile(std::filesystem::path final_path);
  ~AtomicFile();  // removes the temporary file unless committed
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ostream& Stream() { return out_; }
  const std::filesystem::path& TempPath() const { return temp_; }
  // Flushes, checks the stream and renames into place. Throws squint::Error on failure.
  void Commit();

 private:
  std::filesystem::path final_;
  std::filesystem::path temp_;
  std::ofstream out_;
  bool committed_ = false;
};

// Writes a whole string to a file atomically.
void WriteFileAtomically(const std::filesystem::path& path, const std::string& contents);

// A folder output: write everything under Path(); Commit() moves each entry into the final
// folder (creating it, replacing entries of the same name, keeping others). Without Commit()
// the staging folder is removed and the destination is untouched.
class StagedDirectory {
 public:
  explicit StagedDirectory(std::filesystem::path final_dir);
  ~StagedDirectory();
  StagedDirectory(const StagedDirectory&) = delete;
  StagedDirectory& operator=(const StagedDirectory&) = delete;

  const std::filesystem::path& Path() const { return staging_; }
  const std::filesystem::path& FinalPath() const { return final_; }
  void Commit();

 private:
  std::filesystem::path final_;
  std::filesystem::path staging_;
  bool committed_ = false;
};

}  // namespace squint::io
