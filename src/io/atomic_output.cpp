// Outputs that appear whole or not at all (temporary name + rename).
#include "squint/io/atomic_output.hpp"

#include <atomic>
#include <system_error>
#include <unistd.h>

#include "squint/core/error.hpp"

namespace squint::io {
namespace fs = std::filesystem;

namespace {
fs::path TempSibling(const fs::path& final_path, const char* tag) {
  static std::atomic<int> counter{0};
  const fs::path parent = final_path.has_parent_path() ? final_path.parent_path() : fs::path(".");
  return parent / ("." + final_path.filename().string() + "." + tag + "-" + std::to_string(::getpid()) + "-" +
                   std::to_string(counter++));
}
void EnsureParent(const fs::path& p) {
  if (!p.has_parent_path()) return;
  std::error_code ec;
  fs::create_directories(p.parent_path(), ec);
  if (ec) throw Error("cannot create folder " + p.parent_path().string() + ": " + ec.message());
}
}  // namespace

AtomicFile::AtomicFile(fs::path final_path) : final_(std::move(final_path)) {
  if (final_.empty()) throw Error("output path is empty");
  EnsureParent(final_);
  temp_ = TempSibling(final_, "tmp");
  out_.open(temp_, std::ios::out | std::ios::trunc | std::ios::binary);
  if (!out_) throw Error("cannot write " + final_.string());
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    out_.close();
    std::error_code ec;
    fs::remove(temp_, ec);
  }
}

void AtomicFile::Commit() {
  out_.flush();
  const bool ok = static_cast<bool>(out_);
  out_.close();
  if (!ok) throw Error("failed while writing " + final_.string());
  std::error_code ec;
  fs::rename(temp_, final_, ec);
  if (ec) throw Error("cannot move output into place at " + final_.string() + ": " + ec.message());
  committed_ = true;
}

void WriteFileAtomically(const fs::path& path, const std::string& contents) {
  AtomicFile f(path);
  f.Stream() << contents;
  f.Commit();
}

StagedDirectory::StagedDirectory(fs::path final_dir) : final_(std::move(final_dir)) {
  if (final_.empty()) throw Error("output folder path is empty");
  if (fs::exists(final_) && !fs::is_directory(final_))
    throw Error("output " + final_.string() + " exists and is not a folder");
  fs::path clean = final_.lexically_normal();
  if (clean.filename().empty()) clean = clean.parent_path();
  EnsureParent(clean);
  staging_ = TempSibling(clean, "staging");
  std::error_code ec;
  fs::create_directories(staging_, ec);
  if (ec) throw Error("cannot create staging folder " + staging_.string() + ": " + ec.message());
}

StagedDirectory::~StagedDirectory() {
  if (!committed_) {
    std::error_code ec;
    fs::remove_all(staging_, ec);
  }
}

void StagedDirectory::Commit() {
  std::error_code ec;
  fs::create_directories(final_, ec);
  if (ec) throw Error("cannot create folder " + final_.string() + ": " + ec.message());
  for (const auto& entry : fs::directory_iterator(staging_)) {
    const fs::path target = final_ / entry.path().filename();
    if (fs::exists(target)) fs::remove_all(target, ec);
    fs::rename(entry.path(), target, ec);
    if (ec) throw Error("cannot move " + entry.path().filename().string() + " into " + final_.string() + ": " + ec.message());
  }
  fs::remove_all(staging_, ec);
  committed_ = true;
}

}  // namespace squint::io
