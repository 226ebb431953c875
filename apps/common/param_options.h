// A library params table (dhdr/common/param_table.h) as a tool's options: the option, its
// range or choices and its default in --help all come from the table and the struct.
#pragma once

#include "command_line.h"

#include <cmath>
#include <dhdr/common/param_table.h>
#include <vector>

namespace dhdr::app {

// Registers one option per row of `table`, writing into `params`, whose current values are
// the defaults shown.
template <class Params, size_t N>
void addParamOptions(CommandLine& cl, Params& params, const IntParam<Params> (&table)[N]) {
    for (const IntParam<Params>& p : table)
        cl.option(p.option, params.*(p.field), p.metavar, p.help, p.min, p.max);
}

template <class Params, class T, size_t N>
void addParamOptions(CommandLine& cl, Params& params, const FloatParam<Params, T> (&table)[N]) {
    for (const FloatParam<Params, T>& p : table)
        cl.option(p.option, params.*(p.field), p.metavar, p.help, p.range);
}

// "NX,NY,NZ": exactly as many whole numbers as the field holds, each in the row's range.
template <class Params, class Vec, size_t N>
void addParamOptions(CommandLine& cl, Params& params, const IntVecParam<Params, Vec> (&table)[N]) {
    for (const IntVecParam<Params, Vec>& p : table)
        cl.option(p.option, p.metavar, std::string(p.help) + ", each in " + intRangeText(p),
                  [&params, &p](const std::string& v, std::string& error) {
                      Vec counts{};
                      std::vector<double> numbers;
                      bool ok = parseNumbers(v, numbers, size_t(counts.length()));
                      for (size_t i = 0; ok && i < numbers.size(); ++i) {
                          ok = numbers[i] == std::floor(numbers[i]) && numbers[i] >= p.min &&
                               numbers[i] <= p.max;
                          counts[int(i)] = ok ? int(numbers[i]) : 0;
                      }
                      if (!ok)
                          error = "'" + v + "' is not " + std::to_string(counts.length()) +
                                  " whole numbers in " + intRangeText(p);
                      else
                          params.*(p.field) = counts;
                      return ok;
                  });
}

template <class Params, size_t N>
void addParamOptions(CommandLine& cl, Params& params, const ChoiceParam<Params> (&table)[N]) {
    for (const ChoiceParam<Params>& p : table)
        cl.option(p.option, p.names,
                  std::string(p.help) + " (default " + choiceName(p.names, p.get(params)) + ")",
                  [&params, &p](const std::string& v, std::string& error) {
                      const int index = choiceIndex(p.names, v);
                      if (index < 0)
                          error = "must be " + choiceList(p.names) + ", not '" + v + "'";
                      else
                          p.set(params, index);
                      return index >= 0;
                  });
}

template <class Params, size_t N>
void addParamOptions(CommandLine& cl, Params& params, const FlagParam<Params> (&table)[N]) {
    for (const FlagParam<Params>& p : table)
        cl.flag(
            p.option, [&params, &p] { p.set(params, !p.negated); }, p.help);
}

} // namespace dhdr::app
