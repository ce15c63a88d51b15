// tests/base/test_huge_pages.cpp: the regions of core/base/huge_pages.h (alignment, size, the kernel's MADV_HUGEPAGE
// flag on the mapping), and the data moved into them: a scene's texels (pack_texels) keep their lookups bit for bit and
// stay valid through copies, moves and the end of the vector they were packed in; the packed hit records of a
// TraceableScene are pack_triangles' records in a region.
// Test kinds: unit
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "core/base/huge_pages.h"
#include "core/render/traceable_scene.h"
#include "core/sampling/rng.h"
#include "core/scene/texture.h"
#include "tests/support/scenes.h"

namespace pv {
namespace {

bool same_bits(vec4 a, vec4 b) { return std::memcmp(&a, &b, sizeof(vec4)) == 0; }

uintptr_t address(const void* p) { return reinterpret_cast<uintptr_t>(p); }

// The VmFlags line of the mapping in /proc/self/smaps that holds address p ("" if none is found).
std::string vm_flags_at(const void* p) {
    std::ifstream smaps("/proc/self/smaps");
    std::string line;
    bool inside = false;
    while (std::getline(smaps, line)) {
        unsigned long lo = 0, hi = 0;
        char dash = 0;
        std::istringstream head(line);
        if (head >> std::hex >> lo >> dash >> hi && dash == '-' && line.find(':') > line.find(' ')) {
            inside = address(p) >= lo && address(p) < hi;
        } else if (inside && line.rfind("VmFlags:", 0) == 0) {
            return line;
        }
    }
    return "";
}

TEST(HugePages, RegionsAreAlignedAndRoundedUp) {
    // From 1 MiB up: 2 MiB aligned, whole 2 MiB pages, less than one page of tail; below: 64-byte aligned.
    for (const size_t bytes : {kHugePageMinBytes, size_t(3 << 20) + 5, size_t(4) << 20}) {
        const std::shared_ptr<std::byte> r = allocate_region(bytes);
        EXPECT_EQ(address(r.get()) % kHugePageBytes, 0u) << bytes;
        const size_t capacity = region_capacity(bytes);
        EXPECT_EQ(capacity % kHugePageBytes, 0u);
        EXPECT_GE(capacity, bytes);
        EXPECT_LT(capacity - bytes, kHugePageBytes);
        for (const size_t i : {size_t(0), bytes / 2, bytes - 1}) EXPECT_EQ(r.get()[i], std::byte(0));
    }
    for (const size_t bytes : {size_t(1), size_t(100), kHugePageMinBytes - 1}) {
        const std::shared_ptr<std::byte> r = allocate_region(bytes);
        EXPECT_EQ(address(r.get()) % 64, 0u) << bytes;
        EXPECT_EQ(region_capacity(bytes), (bytes + 63) / 64 * 64);
        EXPECT_EQ(r.get()[bytes - 1], std::byte(0));
    }
}

TEST(HugePages, LargeRegionsAreAdvised) {
    // The kernel marks a mapping advised MADV_HUGEPAGE with "hg" in its VmFlags: a deterministic check (whether it
    // finds a free huge page to back the region with is not, so AnonHugePages is not asserted).
    if (!std::ifstream("/sys/kernel/mm/transparent_hugepage/enabled") || !std::ifstream("/proc/self/smaps"))
        GTEST_SKIP() << "no transparent huge pages or no /proc/self/smaps";
    const std::shared_ptr<std::byte> r = allocate_region(size_t(3) << 20);
    const std::string flags = vm_flags_at(r.get());
    ASSERT_FALSE(flags.empty());
    EXPECT_NE(flags.find(" hg"), std::string::npos) << flags;
    const std::string last = vm_flags_at(r.get() + (size_t(4) << 20) - 1);  // the mapping covers the whole region
    EXPECT_NE(last.find(" hg"), std::string::npos) << last;
}

// Textures of odd sizes, code-tiled and float, one of them above kHugePageMinBytes by itself.
std::vector<Texture> odd_textures() {
    Pcg32 rng(7, 3);
    std::vector<Texture> t;
    for (const ivec2 size : {ivec2(5, 3), ivec2(1, 1), ivec2(13, 7), ivec2(600, 457)}) {
        std::vector<uint32_t> codes(size_t(size.x) * size_t(size.y));
        for (uint32_t& c : codes) c = rng.next_u32();
        t.emplace_back(size.x, size.y, std::move(codes));
    }
    for (const ivec2 size : {ivec2(7, 9), ivec2(3, 1)}) {
        std::vector<vec4> texels(size_t(size.x) * size_t(size.y));
        for (vec4& v : texels) v = vec4(rng.next_float() * 3.f, rng.next_float(), 0.3f, rng.next_float());
        t.emplace_back(size.x, size.y, std::move(texels));
    }
    t.emplace_back();  // empty: lookups give 1
    return t;
}

// Every texture of `a` and `b` returns the same bits at the same uvs (inside, outside [0, 1], on texel centres).
void expect_same_lookups(const std::vector<Texture>& a, const std::vector<Texture>& b) {
    ASSERT_EQ(a.size(), b.size());
    Pcg32 rng(11, 5);
    for (size_t k = 0; k < a.size(); ++k)
        for (int i = 0; i < 2000; ++i) {
            const vec2 uv(rng.next_float() * 5.f - 2.f, rng.next_float() * 5.f - 2.f);
            ASSERT_TRUE(same_bits(a[k].lookup(uv), b[k].lookup(uv))) << k << " at " << uv.x << ", " << uv.y;
            ASSERT_TRUE(same_bits(a[k].lookup(a[k].prefetch(uv)), b[k].lookup(b[k].prefetch(uv))));
        }
}

TEST(HugePages, PackedTexelsGiveTheSameLookups) {
    std::vector<Texture> packed = odd_textures();
    const std::vector<Texture> before = odd_textures();
    const std::vector<Texture> copies = packed;  // copies made before packing keep their own storage
    pack_texels(packed);
    expect_same_lookups(before, packed);
    expect_same_lookups(before, copies);
    for (size_t k = 0; k < packed.size(); ++k) {
        EXPECT_EQ(packed[k].bytes(), before[k].bytes());
        EXPECT_EQ(packed[k].texels(), before[k].texels());
        if (packed[k].bytes() > 0) {
            EXPECT_NE(packed[k].storage(), copies[k].storage());
        }
    }
    // One region, the textures 64-byte aligned in packing order, without overlap; more than 1 MiB: on 2 MiB pages.
    EXPECT_EQ(address(packed[0].storage()) % kHugePageBytes, 0u);
    uintptr_t end = address(packed[0].storage());
    for (const Texture& t : packed) {
        if (t.bytes() == 0) continue;
        EXPECT_EQ(address(t.storage()) % 64, 0u);
        EXPECT_GE(address(t.storage()), end);
        EXPECT_LT(address(t.storage()) - end, 64u);
        end = address(t.storage()) + t.bytes();
    }
    EXPECT_LT(end - address(packed[0].storage()), region_capacity(kHugePageMinBytes + 1));
}

TEST(HugePages, PackedTexelsOutliveTheirVectorThroughCopiesAndMoves) {
    const std::vector<Texture> reference = odd_textures();
    std::vector<Texture> survivors;
    Texture moved_from;
    {
        std::vector<Texture> packed = odd_textures();
        pack_texels(packed);
        survivors.push_back(packed[3]);             // a copy shares the region
        survivors.push_back(std::move(packed[0]));  // a move takes the texture's share
        Texture assigned;
        assigned = packed[4];
        survivors.push_back(std::move(assigned));
        moved_from = std::move(packed[1]);
        survivors.push_back(moved_from);
        Texture left = std::move(moved_from);  // moved from: an empty texture
        EXPECT_EQ(moved_from.bytes(), 0u);
        EXPECT_TRUE(same_bits(moved_from.lookup(vec2(0.3f, 0.6f)), vec4(1.f)));
        EXPECT_TRUE(same_bits(moved_from.lookup(moved_from.prefetch(vec2(0.3f, 0.6f))), vec4(1.f)));
    }  // the vector packed in is gone; the region lives while a texture points into it (ASan checks the reads)
    expect_same_lookups({reference[3], reference[0], reference[4], reference[1]}, survivors);
    // Packing again (a scene gaining an environment map) moves them into a new region; lookups unchanged.
    pack_texels(survivors);
    expect_same_lookups({reference[3], reference[0], reference[4], reference[1]}, survivors);
}

TEST(HugePages, TriangleRecordsLiveInARegion) {
    // 20000 triangles: 1.2 MiB of records, on 2 MiB pages; the records are pack_triangles' bit for bit.
    auto s = std::make_shared<Scene>();
    test::add_material(*s, Material{});
    Pcg32 rng(5, 9);
    for (int i = 0; i < 20000; ++i) {
        const vec3 a(rng.next_float() * 10.f, rng.next_float() * 10.f, rng.next_float() * 10.f);
        s->add_triangle(a, a + vec3(0.1f, 0.f, 0.f), a + vec3(0.f, 0.1f, 0.02f), 0);
    }
    const std::vector<TriangleRecord> expected = pack_triangles(*s);
    const TraceableScene ts(s);
    ASSERT_NE(ts.triangle_record(0), nullptr);
    EXPECT_EQ(address(ts.triangle_record(0)) % kHugePageBytes, 0u);
    EXPECT_EQ(std::memcmp(ts.triangle_record(0), expected.data(), expected.size() * sizeof(TriangleRecord)), 0);
}

}  // namespace
}  // namespace pv
