// Where the file behind a URDF mesh URI lies, without ROS: package:// names a package, which
// ROS finds by its package.xml somewhere under ROS_PACKAGE_PATH; without ROS the robot's
// own folders are the place to look.
#include <tinyxml.h>

#include <cstdlib>
#include <filesystem>
#include <system_error>

#include "loaders/pfx_urdf_internal.h"

namespace pfx {

namespace fs = std::filesystem;

namespace {

bool isFile(const fs::path& path) {
  std::error_code error;
  return fs::is_regular_file(path, error);
}

// The <name> that a package.xml in `folder` declares, or empty.
std::string packageName(const fs::path& folder) {
  const fs::path manifest = folder / "package.xml";
  if (!isFile(manifest)) return std::string();
  TiXmlDocument document(manifest.string());
  if (!document.LoadFile()) return std::string();
  const TiXmlElement* root = document.RootElement();
  const TiXmlElement* name = root ? root->FirstChildElement("name") : nullptr;
  return name && name->GetText() ? std::string(name->GetText()) : std::string();
}

// The folder of package `name` below one entry of ROS_PACKAGE_PATH, searched as deep as
// catkin workspaces nest packages; empty when it is not there.
fs::path findPackage(const fs::path& entry, const std::string& name) {
  constexpr int kMaxDepth = 4;
  std::error_code error;
  if (packageName(entry) == name) return entry;
  fs::recursive_directory_iterator it(entry, fs::directory_options::skip_permission_denied, error);
  for (; !error && it != fs::recursive_directory_iterator(); it.increment(error)) {
    const fs::path& path = it->path();
    const bool hidden = !path.filename().empty() && path.filename().string()[0] == '.';
    if (!it->is_directory(error) || hidden) {
      if (hidden) it.disable_recursion_pending();
      continue;
    }
    if (packageName(path) == name) return path;
    // A package does not hold other packages.
    if (fs::exists(path / "package.xml", error) || it.depth() + 1 >= kMaxDepth) {
      it.disable_recursion_pending();
    }
  }
  return fs::path();
}

std::vector<fs::path> packageCandidates(const std::string& package, const std::string& rest,
                                        const fs::path& urdfFolder,
                                        const std::string& packageRoot) {
  std::vector<fs::path> candidates;
  if (const char* rosPackagePath = std::getenv("ROS_PACKAGE_PATH")) {
    std::string entries = rosPackagePath;
    std::size_t begin = 0;
    while (begin <= entries.size()) {
      const std::size_t end = std::min(entries.find(':', begin), entries.size());
      const std::string entry = entries.substr(begin, end - begin);
      if (!entry.empty()) {
        const fs::path folder = findPackage(entry, package);
        if (!folder.empty()) candidates.push_back(folder / rest);
      }
      begin = end + 1;
    }
  }
  if (!packageRoot.empty()) candidates.push_back(fs::path(packageRoot) / rest);
  std::error_code error;
  fs::path folder = fs::absolute(urdfFolder.empty() ? fs::path(".") : urdfFolder, error);
  for (; !error && !folder.empty(); folder = folder.parent_path()) {
    candidates.push_back(folder / rest);
    if (folder == folder.root_path()) break;
  }
  return candidates;
}

}  // namespace

bool pfxResolveUrdfMeshUri(const std::string& uri, const std::string& urdfFolder,
                           const std::string& packageRoot, std::string& path,
                           std::string& searched) {
  static const std::string kPackage = "package://";
  static const std::string kFile = "file://";
  std::vector<fs::path> candidates;
  if (uri.compare(0, kPackage.size(), kPackage) == 0) {
    const std::string target = uri.substr(kPackage.size());
    const std::size_t slash = target.find('/');
    if (slash == std::string::npos || slash == 0) {
      searched = "a package:// URI names a package and a file in it";
      return false;
    }
    candidates = packageCandidates(target.substr(0, slash), target.substr(slash + 1), urdfFolder,
                                   packageRoot);
  } else {
    const bool isFileUri = uri.compare(0, kFile.size(), kFile) == 0;
    const std::string file = isFileUri ? uri.substr(kFile.size()) : uri;
    if (!isFileUri && file.find("://") != std::string::npos) {
      searched = "only package:// and file:// URIs and paths are read";
      return false;
    }
    const fs::path given(file);
    candidates.push_back(given.is_absolute() ? given : fs::path(urdfFolder) / given);
  }
  searched.clear();
  for (const fs::path& candidate : candidates) {
    if (isFile(candidate)) {
      path = candidate.lexically_normal().string();
      return true;
    }
    searched += (searched.empty() ? "" : ", ") + candidate.lexically_normal().string();
  }
  searched = "looked for " + searched;
  return false;
}

}  // namespace pfx
