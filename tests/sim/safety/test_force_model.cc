// The force-model asset: a valid file reads back as written; every way a file can be wrong is refused
// with the JSON field named; predictions follow the posynomial and scale up outside the ranges.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>

#include "sim/safety/force_model.h"
#include "force_model_fixture.h"

using namespace culinarycut;
using namespace culinarycut::safety;

namespace {

nlohmann::json Valid() { return testing::ForceModelDocument({{2.0, {1, 0, 0, 0, 1}}, {0.5, {0, 0, 0, 1, 1}}}); }

}  // namespace

TEST_CASE("a valid force model reads back as written", "[safety][force_model]") {
  const ForceModel model = ParseForceModel(Valid().dump());
  REQUIRE(model.terms.size() == 2);
  CHECK(model.terms[1].coefficient == 0.5);
  CHECK(model.terms[1].exponents[3] == 1.0);
  CHECK(model.ranges[0].high == 4.0);
  CHECK(model.out_of_range_factor == 1.5);
  CHECK(model.fit.samples == 10);
  CHECK(model.quality == "draft");
}

TEST_CASE("a bad force model is refused with the JSON field named", "[safety][force_model]") {
  using nlohmann::json;
  const auto refused_naming = [](const json& document, const std::string& field) {
    INFO(document.dump());
    CHECK_THROWS_WITH(ParseForceModel(document.dump()), Catch::StartsWith(field));
  };
  json document = Valid();
  document["format"] = "something.else";
  refused_naming(document, "format");
  document = Valid();
  document["version"] = 2;
  refused_naming(document, "version");
  document = Valid();
  document["terms"][1]["coefficient"] = -0.1;
  refused_naming(document, "terms[1].coefficient");
  document = Valid();
  document["terms"][0]["exponents"][2] = -1;
  refused_naming(document, "terms[0].exponents[2]");
  document = Valid();
  document["terms"][0]["exponents"] = {1, 0, 1};
  refused_naming(document, "terms[0].exponents");
  document = Valid();
  document["inputs"][1] = "youngs_modulus_pa";
  refused_naming(document, "inputs");
  document = Valid();
  document["ranges"].erase("edge_length_m");
  refused_naming(document, "ranges.edge_length_m");
  document = Valid();
  document["out_of_range_factor"] = 0.5;
  refused_naming(document, "out_of_range_factor");
  document = Valid();
  document["fit"].erase("rmse_n");
  refused_naming(document, "fit.rmse_n");
  // JSON has no NaN or infinity; a literal past a double is refused by the parser, quoting it.
  std::string text = Valid().dump();
  text.replace(text.find("0.5"), 3, "1e999");
  CHECK_THROWS_WITH(ParseForceModel(text), Catch::Contains("not valid JSON") && Catch::Contains("1e999"));
  CHECK_THROWS_WITH(ParseForceModel("{not json"), Catch::Contains("not valid JSON"));
}

TEST_CASE("a missing file is refused with its path", "[safety][force_model]") {
  CHECK_THROWS_WITH(LoadForceModel("/nonexistent/force_model.json"), Catch::StartsWith("/nonexistent/force_model.json"));
}

TEST_CASE("the prediction is the posynomial, scaled by the out-of-range factor outside the ranges", "[safety][force_model]") {
  const ForceModel model = ParseForceModel(Valid().dump());
  const CutMaterial cucumber{1.0, 10.0, 100.0, 0.04};
  const ForcePrediction inside = PredictPeakForce(model, 0.5, cucumber);
  CHECK_FALSE(inside.out_of_range);
  CHECK(inside.force_n == Approx(2.0 * 0.5 * 0.04 + 0.5 * 100.0 * 0.04));
  CutMaterial stiff = cucumber;
  stiff.youngs_modulus_mpa = 80.0;  // above the range: E does not enter these terms, the factor still applies
  const ForcePrediction outside = PredictPeakForce(model, 0.5, stiff);
  CHECK(outside.out_of_range);
  CHECK(outside.force_n == Approx(1.5 * inside.force_n));
  CHECK(PredictPeakForce(model, 5.0, cucumber).out_of_range);  // faster than the data went
}

TEST_CASE("the test asset the server tests use is a valid force model", "[safety][force_model]") {
  const ForceModel model = LoadForceModel(CULINARYCUT_TEST_FORCE_MODEL);
  CHECK_FALSE(model.terms.empty());
}
