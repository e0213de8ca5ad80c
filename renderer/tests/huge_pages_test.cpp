#include "util/huge_pages.h"

#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace rt {
namespace {

struct alignas(32) Row {
    float v[8];
};

// The kernel's transparent huge page mode: "always", "madvise" or "never".
std::string thp_mode() {
    std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string line;
    std::getline(in, line);
    const size_t open = line.find('['), close = line.find(']');
    return open == std::string::npos ? "never" : line.substr(open + 1, close - open - 1);
}

// /proc/self/smaps's THPeligible for the mapping holding p: whether the
// kernel may back it with huge pages (-1 when no mapping holds it).
int thp_eligible(const void* p) {
    const uintptr_t at = reinterpret_cast<uintptr_t>(p);
    std::ifstream smaps("/proc/self/smaps");
    bool inside = false;
    for (std::string line; std::getline(smaps, line);) {
        uintptr_t begin = 0, end = 0;
        char dash = 0;
        std::istringstream head(line);
        if (head >> std::hex >> begin >> dash >> end && dash == '-') {
            inside = begin <= at && at < end;
        } else if (inside && line.rfind("THPeligible:", 0) == 0) {
            return std::stoi(line.substr(12));
        }
    }
    return -1;
}

TEST(HugePages, LargeArraysStartOnAHugePageAndAreAdvised) {
    if (!huge_pages::kMapsArrays) GTEST_SKIP() << "AddressSanitizer build: every array comes from operator new";
    HugePageVector<Row> rows(3 * huge_pages::kPageBytes / sizeof(Row) + 5);
    EXPECT_EQ(reinterpret_cast<uintptr_t>(rows.data()) % huge_pages::kPageBytes, 0u);
    if (thp_mode() != "never") {
        EXPECT_EQ(thp_eligible(rows.data()), 1) << "mode " << thp_mode();
    }
}

TEST(HugePages, SmallArraysKeepTheirAlignmentFromTheHeap) {
    HugePageVector<Row> rows(3);
    EXPECT_EQ(reinterpret_cast<uintptr_t>(rows.data()) % alignof(Row), 0u);
    EXPECT_NE(reinterpret_cast<uintptr_t>(rows.data()) % huge_pages::kPageBytes, 0u);
}

TEST(HugePages, GrowingAcrossTheThresholdKeepsTheContents) {
    HugePageVector<uint32_t> values;
    const uint32_t count = uint32_t(2 * huge_pages::kPageBytes / sizeof(uint32_t));
    for (uint32_t i = 0; i < count; ++i) values.push_back(i * 2654435761u);
    for (uint32_t i = 0; i < count; i += 4099) ASSERT_EQ(values[i], i * 2654435761u);
    values.resize(10);
    values.shrink_to_fit();
    EXPECT_EQ(values[9], 9u * 2654435761u);
}

}  // namespace
}  // namespace rt
