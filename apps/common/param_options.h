// A library params table (dhdr/deferred/core/param_table.h) as a tool's options: the option, its
// range and its default in --help all come from the table and the struct.
#pragma once

#include "command_line.h"

#include <dhdr/deferred/core/param_table.h>

namespace dhdr::app {

// Registers one option per row of `table`, writing into `params`, whose current values are
// the defaults shown.
template <class Params, size_t N>
void addParamOptions(CommandLine& cl, Params& params, const IntParam<Params> (&table)[N]) {
    for (const IntParam<Params>& p : table)
        cl.option(p.option, params.*(p.field), p.metavar,
                  std::string(p.help) + " (default " + std::to_string(params.*(p.field)) + ")",
                  p.min, p.max);
}

} // namespace dhdr::app
