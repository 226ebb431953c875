// The options every tool that reads lights takes, with one help text, so that a lights file
// means the same to dhdr-light and dhdr-probes.
#pragma once

#include "command_line.h"

namespace dhdr::app {

// --radiometric: the lights' intensities are photometric (Blender's glTF export) and are
// divided by 683 lm/W (dhdr::toRadiometricUnits).
inline void addLightUnitsOption(CommandLine& cl, bool& radiometric) {
    cl.flag("--radiometric", radiometric,
            "divide photometric light units (point and spot candela, directional lux) by 683 "
            "lm/W, so that lights exported by Blender light as they do in Cycles; emission "
            "and environments are unchanged");
}

} // namespace dhdr::app
