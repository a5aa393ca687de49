// The registry's answers about a model (mechanism/registry.hpp): what callers ask instead of
// testing a model's name.
#include <gtest/gtest.h>

#include <set>
#include <stdexcept>

#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/registry.hpp"
#include "mire/mechanism/variants.hpp"

namespace mech = mire::mechanism;

TEST(Registry, EveryVariantBelongsToExactlyOneModelOfItsKind) {
  std::set<char> seen;
  for (const mech::ModelInfo& info : mech::registeredModels()) {
    if (info.variants.empty()) {
      EXPECT_EQ(info.default_variant, 0) << info.name;
      continue;
    }
    EXPECT_NE(info.variants.find(info.default_variant), std::string::npos) << info.name;
    const mech::RegisteredModel model = mech::makeRegisteredModel(info.name);
    for (const char letter : info.variants) {
      EXPECT_TRUE(seen.insert(letter).second) << letter << " in two models";
      EXPECT_EQ(&mech::modelOfVariant(letter), &info);
      // The variant's preset is of this model's kinematics (its parameter names).
      const mech::H4Variant& variant = mech::h4Variant(letter);
      EXPECT_EQ(mech::makeH4Mechanism(variant.model)->nominal().names(), model.nominal.names()) << letter;
    }
  }
  EXPECT_EQ(seen, (std::set<char>{'A', 'B', 'C', 'D', 'E', 'F', 'G', 'H'}));
  EXPECT_THROW(mech::modelOfVariant('Z'), std::invalid_argument);
}

TEST(Registry, TheH4NominalReachesExactlyTheModelsThatSayTheyTakeIt) {
  mech::H4Nominal larger;
  larger.R = 0.30;
  for (const mech::ModelInfo& info : mech::registeredModels()) {
    const bool changed = mech::makeRegisteredModel(info.name, larger).nominal.values() !=
                         mech::makeRegisteredModel(info.name).nominal.values();
    EXPECT_EQ(changed, info.h4_nominal) << info.name;
    EXPECT_FALSE(info.label.empty()) << info.name;
  }
  EXPECT_EQ(&mech::modelInfo(mech::registeredModels().front().name), &mech::registeredModels().front());
  EXPECT_THROW(mech::modelInfo("nope"), std::invalid_argument);
}
