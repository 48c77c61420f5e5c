#include "procedural/glass_and_water.h"

#include <gtest/gtest.h>

#include "procedural/textures.h"

namespace rigsim::procedural {
namespace {

TEST(GlassAndWater, PuddlesCoverTheAskedShareInsideTheirGround) {
  const float x0 = -5, z0 = 20, x1 = 5, z1 = 30, y = 0.15f;
  for (const float wet : {0.05f, 0.1f, 0.2f}) {
    SCOPED_TRACE(wet);
    Rng rng(7);
    const MeshData m = Puddles(rng, x0, z0, x1, z1, y, wet);
    const float area = GroundArea(m), target = wet * (x1 - x0) * (z1 - z0);
    // Puddles are added until they reach the share; the last one overshoots by at most its own area
    // (the largest: 1.3 x 1.0 m by 1.3 x 2.0 m semi-axes).
    EXPECT_GE(area, target);
    EXPECT_LT(area, target + kPi * 1.3f * 1.3f * 2.0f);
    ASSERT_EQ(m.positions.size(), m.texcoords.size());
    ASSERT_EQ(m.positions.size(), m.normals.size());
    for (size_t i = 0; i < m.positions.size(); ++i) {
      const Eigen::Vector3f& p = m.positions[i];
      EXPECT_FLOAT_EQ(p.y(), y + kPuddleHeightM);
      EXPECT_GE(p.x(), x0 + 0.2f);
      EXPECT_LE(p.x(), x1 - 0.2f);
      EXPECT_GE(p.z(), z0 + 0.2f);
      EXPECT_LE(p.z(), z1 - 0.2f);
      // The ground's own texture beneath: u along x, v along z over the rectangle.
      EXPECT_NEAR(m.texcoords[i].x(), (p.x() - x0) / (x1 - x0), 1e-5);
      EXPECT_NEAR(m.texcoords[i].y(), (p.z() - z0) / (z1 - z0), 1e-5);
    }
    for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {  // counter-clockwise seen from above
      const Eigen::Vector3f a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]], c = m.positions[m.indices[t + 2]];
      EXPECT_GT((b - a).cross(c - a).y(), 0.f) << "triangle " << t / 3;
    }
  }
}

TEST(GlassAndWater, PuddlesAreSeededAndNoneWhenDry) {
  Rng a(3), b(3), c(4), dry(3);
  const MeshData ma = Puddles(a, 0, 0, 10, 10, 0, 0.2f), mb = Puddles(b, 0, 0, 10, 10, 0, 0.2f), mc = Puddles(c, 0, 0, 10, 10, 0, 0.2f);
  EXPECT_EQ(ma.positions, mb.positions);
  EXPECT_EQ(ma.indices, mb.indices);
  EXPECT_NE(ma.positions, mc.positions);
  EXPECT_TRUE(Puddles(dry, 0, 0, 10, 10, 0, 0.f).positions.empty());
  EXPECT_EQ(dry.Next(), Rng(3).Next());  // and draw nothing
}

TEST(GlassAndWater, PanesAreTheFacadesWindowsInFrontOfIt) {
  const float width = 12, height = 14, ppm = 20;
  std::vector<Pane> panes;
  const Canvas with = PaintFacade(11, width, height, ppm, &panes);
  // Recording the panes paints the same facade.
  EXPECT_EQ(with.px, PaintFacade(11, width, height, ppm).px);
  ASSERT_GE(panes.size(), 4u);  // upper-floor windows at least
  // A facade at x = 9 facing -x (right = +z), as the street's right side stands.
  const Eigen::Vector3f tl(9, height, -3), right(0, 0, width), down(0, -height, 0);
  const MeshData glass = GlassPanes(tl, right, down, with.w, with.h, panes);
  ASSERT_EQ(glass.positions.size(), 4 * panes.size());
  for (size_t i = 0; i < glass.positions.size(); ++i) {
    const Eigen::Vector3f& p = glass.positions[i];
    EXPECT_FLOAT_EQ(p.x(), 9 - kWindowGlassOffsetM);  // in front of the facade, on the street's side
    EXPECT_EQ(glass.normals[i], Eigen::Vector3f(-1, 0, 0));
    // Each corner shows the facade's texel at the same place: u along the facade, v down it.
    EXPECT_NEAR(glass.texcoords[i].x(), (p.z() - tl.z()) / width, 1e-5);
    EXPECT_NEAR(glass.texcoords[i].y(), (tl.y() - p.y()) / height, 1e-5);
  }
}

}  // namespace
}  // namespace rigsim::procedural
