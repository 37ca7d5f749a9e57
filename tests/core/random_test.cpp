// placeholder: filled by the module work
#include <gtest/gtest.h>
