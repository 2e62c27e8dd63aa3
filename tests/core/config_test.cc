#include "core/config.h"
#include <gtest/gtest.h>
TEST(Placeholder, Builds) {}
