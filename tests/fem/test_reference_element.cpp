// The runtime facade: lookup by Gmsh type, dispatch to the element classes, errors.
#include <gtest/gtest.h>

#include <string>

#include "shellflow/core/error.h"
#include "shellflow/fem/reference_element.h"

namespace shellflow::fem {
namespace {

TEST(ReferenceElement, EveryGmshTypeIsFoundAndDescribesItsClass) {
  ASSERT_EQ(supported_gmsh_types().size(), 9u);
  for (int type : supported_gmsh_types()) {
    const ReferenceElement& re = reference_element(type);
    EXPECT_EQ(re.gmsh_type, type);
    EXPECT_EQ(find_reference_element(type), &re);
    visit_element_type(type, [&](auto e) {
      using E = decltype(e);
      EXPECT_EQ(E::gmsh_type, type);
      EXPECT_EQ(re.num_nodes, E::num_nodes);
      EXPECT_EQ(re.dim, E::dim);
      EXPECT_EQ(re.order, E::order);
      EXPECT_EQ(re.eval, &E::eval);
      EXPECT_EQ(re.node_coords, E::node_coords.data());
    });
  }
  EXPECT_STREQ(reference_element(21).name, "Tri10");
  EXPECT_STREQ(reference_element(29).name, "Tet20");
}

TEST(ReferenceElement, UnknownTypeThrowsInputErrorNamingIt) {
  EXPECT_EQ(find_reference_element(3), nullptr);
  try {
    (void)reference_element(5);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("element type 5"), std::string::npos) << e.what();
  }
  EXPECT_THROW(visit_element_type(17, [](auto) {}), InputError);
}

TEST(ReferenceElement, VisitReturnsTheCallableResult) {
  const int n = visit_element_type(29, [](auto e) { return decltype(e)::num_nodes; });
  EXPECT_EQ(n, 20);
}

}  // namespace
}  // namespace shellflow::fem
