// The registry's answers about a model (mechanism/registry.hpp): what callers ask instead of
// testing a model's name.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <stdexcept>

#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/model_selection.hpp"
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
  EXPECT_EQ(mech::modelInfo(mech::registeredModels().front().name).name, mech::registeredModels().front().name);
  EXPECT_THROW(mech::modelInfo("nope"), std::invalid_argument);
}

// Every family's entries point at models of the table, and select's default list for its joints
// is its own selection, parseable into candidates of its models.
TEST(Registry, EveryFamilyNamesItsOwnModelsAndItsSelectionParses) {
  std::set<std::string> in_a_family;
  for (const mech::MechanismFamily& family : mech::mechanismFamilies()) {
    ASSERT_FALSE(family.models.empty()) << family.name;
    EXPECT_EQ(&mech::mechanismFamily(family.name), &family);
    EXPECT_NE(std::find(family.models.begin(), family.models.end(), family.truth_model), family.models.end())
        << family.name;
    for (const std::string& name : family.models) {
      EXPECT_EQ(mech::modelInfo(name).family, family.name);
      in_a_family.insert(name);
    }
    const mech::RegisteredModel simplest = mech::makeRegisteredModel(family.models.front());
    EXPECT_EQ(mech::defaultSelectionModels(simplest.mechanism->jointCount(), simplest.mechanism->jointUnits().front()),
              family.selection);
    std::vector<std::string> selected;  // the demo identifies these (selectionModelNames)
    for (const mech::SelectionCandidate& c : mech::parseSelectionCandidates(
             family.selection, [](const std::string& n) { return mech::makeDesignModel(n); })) {
      EXPECT_EQ(mech::modelInfo(c.model.registered.name).family, family.name) << c.label;
      if (selected.empty() || selected.back() != c.model.registered.name) selected.push_back(c.model.registered.name);
    }
    EXPECT_EQ(mech::selectionModelNames(family), selected) << family.name;
    EXPECT_EQ(&mech::familyWithDefects(family.defects), &family);
  }
  EXPECT_EQ(in_a_family.size(), mech::registeredModels().size());
  EXPECT_THROW(mech::mechanismFamily("scara"), std::invalid_argument);
}

// A richer model contains only simpler models of its own family (select's F-tests).
TEST(Registry, ContainmentsAreBetweenModelsOfOneFamilyWithFewerParameters) {
  for (const mech::ModelInfo& richer : mech::registeredModels())
    for (const std::string& name : richer.contains) {
      const mech::ModelInfo& simpler = mech::modelInfo(name);
      EXPECT_EQ(simpler.family, richer.family) << richer.name << " contains " << name;
      EXPECT_LT(mech::makeRegisteredModel(name).nominal.size(), mech::makeRegisteredModel(richer.name).nominal.size());
      for (const std::string& free : richer.contains_when_free)
        EXPECT_TRUE(mech::makeRegisteredModel(richer.name).nominal.contains(free)) << free;
    }
}
