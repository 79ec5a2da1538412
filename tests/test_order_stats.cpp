// Median and quantiles against values worked by hand (type 7: h = q·(n − 1), linear between order
// statistics), in any input order.
#include <gtest/gtest.h>

#include <cmath>

#include "smokescan/core/order_stats.hpp"

using namespace smokescan;

TEST(OrderStats, MedianAndQuantilesByHand)
{
    EXPECT_TRUE(std::isnan(median({})));
    EXPECT_TRUE(std::isnan(quantile({}, 0.3)));
    EXPECT_EQ(median({7.0}), 7.0);
    EXPECT_EQ(quantile({7.0}, 0.9), 7.0);
    EXPECT_EQ(median({5, 1, 3}), 3.0);
    EXPECT_EQ(median({4, 1, 3, 2}), 2.5);  // mean of the two middle values
    EXPECT_EQ(median({2, 2, 9, 2}), 2.0);
    EXPECT_EQ(quantile({5, 4, 3, 2, 1}, 0.25), 2.0);  // h = 1
    EXPECT_DOUBLE_EQ(quantile({4, 1, 3, 2}, 1.0 / 3.0), 2.0);  // h = 1
    EXPECT_DOUBLE_EQ(quantile({40, 10, 30, 20}, 0.8), 34.0);  // h = 2.4: 30 + 0.4·10
    EXPECT_EQ(quantile({3, 1, 2}, 0.0), 1.0);
    EXPECT_EQ(quantile({3, 1, 2}, 1.0), 3.0);
    EXPECT_EQ(quantile({3, 1, 2}, -2.0), 1.0);  // q clamped
    EXPECT_EQ(quantile({3, 1, 2}, 7.0), 3.0);
}
