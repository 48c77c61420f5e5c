// Union-find over dense ids, for the calibrator's grouping of keypoints into tracks and of views
// into what links them. Internal to the calibrator.
#pragma once

#include <algorithm>
#include <vector>

namespace rigsim {

struct UnionFind {
  std::vector<int> parent;
  int Add() {
    parent.push_back(static_cast<int>(parent.size()));
    return parent.back();
  }
  int Find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void Join(int a, int b) {
    a = Find(a);
    b = Find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

}  // namespace rigsim
