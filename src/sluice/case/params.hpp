// The whole case library in one include, for code that uses several parts of it: the parameter
// table, loading, --set overrides, the checks, the template, built-in cases and suggestions.
#pragma once

#include "sluice/case/builtin_cases.hpp"
#include "sluice/case/case_error.hpp"
#include "sluice/case/case_template.hpp"
#include "sluice/case/checks.hpp"
#include "sluice/case/load.hpp"
#include "sluice/case/overrides.hpp"
#include "sluice/case/parameter_table.hpp"
#include "sluice/case/suggest.hpp"
