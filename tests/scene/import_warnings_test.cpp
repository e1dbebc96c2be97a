// The warnings collector both importers share: one line per kind, in order
// of first occurrence, in each of its two forms.
#include "scene/import_warnings.h"

#include <gtest/gtest.h>

namespace {

using vkpath::scene::ImportWarnings;

TEST(SceneImportWarnings, CountedKindsNameTheFirstAndCountTheRest) {
    ImportWarnings warnings("a.gltf");
    warnings.addCounted("textures are ignored", "material", "brick");
    warnings.addCounted("degenerate triangles are dropped", "triangle", "floor", 4);
    warnings.addCounted("textures are ignored", "material", "wood");
    warnings.addCounted("textures are ignored", "node", "ignored: the first unit stays");
    warnings.addCounted("no perspective camera");
    const std::vector<std::string> expected = {
        "a.gltf: textures are ignored (3 materials, first: brick)",
        "a.gltf: degenerate triangles are dropped (4 triangles, first: floor)",
        "a.gltf: no perspective camera"};
    EXPECT_EQ(warnings.lines(), expected);
}

TEST(SceneImportWarnings, ExampleKindsShowTheFirstTextAndHowManyMore) {
    ImportWarnings warnings("b.dae");
    warnings.addExample("skew", "node 'A': <skew> is ignored");
    warnings.addExample("ambient", "light 'Sky': ambient approximated");
    warnings.addExample("skew", "node 'B': <skew> is ignored");
    const std::vector<std::string> expected = {"b.dae: node 'A': <skew> is ignored (2 like this)",
                                               "b.dae: light 'Sky': ambient approximated"};
    EXPECT_EQ(warnings.lines(), expected);
}

TEST(SceneImportWarnings, ReportPrintsEveryLineOnceAndCopiesThem) {
    ImportWarnings warnings("c.dae");
    warnings.addExample("one", "first");
    warnings.addCounted("second", "mesh", "m");
    std::vector<std::string> copy;
    testing::internal::CaptureStderr();
    warnings.report(&copy);
    EXPECT_EQ(testing::internal::GetCapturedStderr(),
              "vkpath: warning: c.dae: first\nvkpath: warning: c.dae: second (1 mesh, first: m)\n");
    EXPECT_EQ(copy, warnings.lines());
}

}  // namespace
