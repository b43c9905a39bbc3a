// Writes the OctoMap files of tests/loaders/data with liboctomap, so that the loader tests
// read files as liboctomap and octomap_server write them. Run with the output folder:
//   build/bin/pfx_make_test_octomaps tests/loaders/data
//
// room.bt     a 8 m x 6 m room at 5 cm (Z up): a 10 cm floor slab, 2.6 m walls two voxels
//             thick with a door in the -Y wall, a table (top at z = 0.75 m) and a cabinet;
//             97,784 occupied voxels, and a layer of free voxels at z = 1.0 .. 1.1 m.
// small.bt    at 10 cm: a 1 m x 1 m plate one voxel thick (top at z = 0), a 20 cm cube on
//             it (pruned by liboctomap into one coarser leaf) and one free voxel beside it;
// small.ot    the same tree in the full format.
// color.ot    a ColorOcTree (not an OcTree) with a few occupied voxels.
// free.bt     an OcTree with free voxels only.
// empty.bt    an OcTree without nodes.
#include <octomap/ColorOcTree.h>
#include <octomap/OcTree.h>

#include <cstdio>
#include <functional>
#include <string>

namespace {

// Cells [lo, hi) per axis, as indices from the origin (cell i spans [i, i + 1) * resolution).
struct CellBox {
  int lo[3];
  int hi[3];
};

template <typename Tree>
void setCells(Tree& tree, const CellBox& box, bool occupied) {
  for (int x = box.lo[0]; x < box.hi[0]; ++x) {
    for (int y = box.lo[1]; y < box.hi[1]; ++y) {
      for (int z = box.lo[2]; z < box.hi[2]; ++z) {
        const octomap::OcTreeKey key(static_cast<octomap::key_type>(32768 + x),
                                     static_cast<octomap::key_type>(32768 + y),
                                     static_cast<octomap::key_type>(32768 + z));
        tree.updateNode(key, occupied);
      }
    }
  }
}

bool writeRoom(const std::string& folder) {
  octomap::OcTree tree(0.05);
  setCells(tree, {{-80, -60, -2}, {80, 60, 0}}, true);    // floor
  setCells(tree, {{-80, -60, 0}, {-78, 60, 52}}, true);   // -X wall
  setCells(tree, {{78, -60, 0}, {80, 60, 52}}, true);     // +X wall
  setCells(tree, {{-78, 58, 0}, {78, 60, 52}}, true);     // +Y wall
  setCells(tree, {{-78, -60, 0}, {-10, -58, 52}}, true);  // -Y wall, left of the door
  setCells(tree, {{8, -60, 0}, {78, -58, 52}}, true);     // -Y wall, right of the door
  setCells(tree, {{-10, -60, 42}, {8, -58, 52}}, true);   // above the door
  setCells(tree, {{-12, -8, 14}, {12, 8, 15}}, true);     // table top
  for (int lx : {-12, 10}) {
    for (int ly : {-8, 6}) setCells(tree, {{lx, ly, 0}, {lx + 2, ly + 2, 14}}, true);  // legs
  }
  setCells(tree, {{60, 40, 0}, {72, 52, 20}}, true);      // cabinet
  setCells(tree, {{-78, -58, 20}, {78, 58, 22}}, false);  // seen free by a sensor
  tree.updateInnerOccupancy();
  return tree.writeBinary(folder + "/room.bt");
}

void fillSmall(octomap::OcTree& tree) {
  setCells(tree, {{-5, -5, -1}, {5, 5, 0}}, true);  // plate
  setCells(tree, {{0, 0, 0}, {2, 2, 2}}, true);     // cube, one aligned 2x2x2 block
  setCells(tree, {{-3, -3, 0}, {-2, -2, 1}}, false);
  tree.updateInnerOccupancy();
  tree.prune();
}

bool writeSmall(const std::string& folder) {
  octomap::OcTree binary(0.1);
  fillSmall(binary);
  octomap::OcTree full(0.1);
  fillSmall(full);
  return binary.writeBinary(folder + "/small.bt") && full.write(folder + "/small.ot");
}

bool writeOthers(const std::string& folder) {
  octomap::ColorOcTree color(0.1);
  setCells(color, {{0, 0, 0}, {2, 1, 1}}, true);
  color.updateInnerOccupancy();
  octomap::OcTree freeOnly(0.1);
  setCells(freeOnly, {{0, 0, 0}, {3, 3, 1}}, false);
  freeOnly.updateInnerOccupancy();
  octomap::OcTree empty(0.1);
  return color.write(folder + "/color.ot") && freeOnly.writeBinary(folder + "/free.bt") &&
         empty.writeBinary(folder + "/empty.bt");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s <output folder>\n", argv[0]);
    return 2;
  }
  const std::string folder = argv[1];
  if (!writeRoom(folder) || !writeSmall(folder) || !writeOthers(folder)) {
    std::fprintf(stderr, "could not write the maps into %s\n", folder.c_str());
    return 1;
  }
  return 0;
}
