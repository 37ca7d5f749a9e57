// fsw/features: Förstner interest points and guided template matching (docs/features.md).
#pragma once

#include "vtm/features/affine_refine.hpp"
#include "vtm/features/forstner.hpp"
#include "vtm/features/template_matcher.hpp"
#include "vtm/features/visibility.hpp"
