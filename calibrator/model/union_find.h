// Union-find over dense ids, for the calibrator's grouping of keypoints into tracks and of views
// into what links them. Internal to the calibrator.
#pragma once

#include <algorithm>
#include <vector>

namespace rigsim {

// The root of a set is its smallest id, so that a set's label does not depend on the order of joins.
struct UnionFind {
  std::vector<int> parent;
  UnionFind() = default;
  // Ids 0 .. n-1, each alone.
  explicit UnionFind(int n) {
    for (int i = 0; i < n; ++i) Add();
  }
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
