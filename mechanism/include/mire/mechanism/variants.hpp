#pragma once
// The identified model variants A–H of the paper's Table 2 (doc/mechanisms.md, "Variants"), as named presets.
//   A: model 12, h and l fixed         10 geometric + 7 external = 17
//   B: model 12, h fixed               11 + 7 = 18
//   C: model 12, l fixed               11 + 7 = 18
//   D: model 12                        12 + 7 = 19
//   E: model 31 (camera frame), one shared L, h and l1..l4 fixed   25 + 3 = 28
//   F: model 31 (camera frame), h and l1..l4 fixed                 28 + 3 = 31
//   G: model 31 (camera frame), l1..l4 fixed                       29 + 3 = 32
//   H: model 31 (camera frame)                                     33 + 3 = 36
// Model-12 variants use the AxisAligned external form (z_ME fixed); model-31 variants the
// CameraFrame form of eq. 25–26 (z_ME fixed).
#include <string>
#include <vector>

#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/identification.hpp"

namespace mire::mechanism {

struct H4Variant {
  char letter = 'D';
  H4ModelKind model = H4ModelKind::Model12;
  ExternalForm external = ExternalForm::AxisAligned;
  std::vector<std::string> fixed;              // geometric names held at a-priori values
  std::vector<std::vector<std::string>> tied;  // groups sharing one value (E: L1..L4)
  int geometric_count = 0;                     // free geometric parameters (Table 2)
  int external_count = 0;                      // free external parameters (Table 2)
  std::string description;
};

const std::vector<H4Variant>& h4Variants();
// Throws std::invalid_argument for a letter outside A–H (case-insensitive).
const H4Variant& h4Variant(char letter);

// The variant's model ready for identify(): nominal geometry, a-priori values fixed, ties
// applied, external values estimated from the poses. Model-31 variants are initialised
// from a preliminary model-12 identification (variant D with `options`) converted to the
// camera frame (model31FromModel12 then model31CameraFromModel31).
IdentificationModel makeH4VariantModel(char letter, const H4Nominal& nominal, const std::vector<PoseObservation>& poses,
                                       const IdentificationOptions& options = {});

// makeH4VariantModel() then identify().
IdentificationResult identifyH4Variant(char letter, const H4Nominal& nominal, const std::vector<PoseObservation>& poses,
                                       const IdentificationOptions& options = {});

}  // namespace mire::mechanism
