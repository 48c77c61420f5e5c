// Colour previews of the exact ground-truth images, to look at in a browser or an image viewer:
// depth (float metres) and instances (uint16 ids). The exact files stay the ones to compute with.
#pragma once

#include "geometry/image.h"

namespace rigsim {

// Range (metres, 0 = no surface) as RGB: a turbo-like colour map on a log scale, red at 1 m and
// nearer through yellow and green to blue at 200 m and beyond, so that colours mean the same
// distance in every view; black where there is no surface.
ImageU8 ColorizeDepth(const ImageF& range);

// Instance ids as RGB: each id its own colour (a hash of the id, the same in every view), black for 0.
ImageU8 ColorizeInstances(const ImageU16& instances);

}  // namespace rigsim
