#include "calibrator/model/two_view_geometry.h"

#include <stdexcept>
#include <string>

namespace rigsim {

std::string_view PairTypeName(PairType type) {
  switch (type) {
    case PairType::kGeneral: return "general";
    case PairType::kPlanar: return "planar";
    case PairType::kRotationOnly: return "rotation-only";
  }
  throw std::invalid_argument("PairTypeName: invalid pair type " + std::to_string(static_cast<int>(type)));
}

}  // namespace rigsim
