// scripts/make_compressed_gltf.cpp: writes the uncompressed original and its Draco-compressed copy of the test mesh
// of tests/data/gltf-compressed (scripts/make_compressed_gltf.sh builds and runs it, then gltfpack writes the meshopt
// and quantized copies). The mesh: a bumpy sphere (32 x 16 quads, positions, normals, texture coordinates).
// Usage: make_compressed_gltf <output folder>
#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

struct Mesh {
    std::vector<float> pos, nrm, uv;
    std::vector<uint32_t> idx;
};

Mesh make_mesh() {
    Mesh m;
    const int nu = 32, nv = 16;
    const double pi = 3.14159265358979323846;
    for (int j = 0; j <= nv; ++j)
        for (int i = 0; i <= nu; ++i) {
            const double u = double(i) / nu, v = double(j) / nv;
            const double th = 2.0 * pi * u, ph = pi * v;
            const double r = 1.0 + 0.15 * std::sin(5.0 * th) * std::sin(3.0 * ph);
            const double x = std::sin(ph) * std::cos(th), y = std::cos(ph), z = std::sin(ph) * std::sin(th);
            m.pos.insert(m.pos.end(), {float(r * x), float(r * y), float(r * z)});
            m.nrm.insert(m.nrm.end(), {float(x), float(y), float(z)});
            m.uv.insert(m.uv.end(), {float(u), float(v)});
        }
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            const uint32_t a = uint32_t(j * (nu + 1) + i), b = a + 1, c = a + uint32_t(nu + 1), d = c + 1;
            if (j > 0) m.idx.insert(m.idx.end(), {a, b, c});
            if (j < nv - 1) m.idx.insert(m.idx.end(), {b, d, c});
        }
    return m;
}

void minmax(const std::vector<float>& v, int n, std::string& mn, std::string& mx) {
    std::ostringstream a, b;
    a.precision(9);
    b.precision(9);
    a << "[";
    b << "[";
    for (int c = 0; c < n; ++c) {
        float lo = v[size_t(c)], hi = v[size_t(c)];
        for (size_t i = size_t(c); i < v.size(); i += size_t(n)) lo = std::min(lo, v[i]), hi = std::max(hi, v[i]);
        a << (c ? "," : "") << lo;
        b << (c ? "," : "") << hi;
    }
    a << "]";
    b << "]";
    mn = a.str();
    mx = b.str();
}

void write(const std::string& path, const std::string& bytes) {
    std::ofstream f(path, std::ios::binary);
    f << bytes;
    if (!f) {
        std::fprintf(stderr, "cannot write %s\n", path.c_str());
        std::exit(1);
    }
}

template <class T>
std::string bytes_of(const std::vector<T>& v) {
    return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: make_compressed_gltf <output folder>\n");
        return 2;
    }
    const std::string dir = argv[1];
    const Mesh m = make_mesh();
    const size_t nv = m.pos.size() / 3;
    std::string pmin, pmax, dummy;
    minmax(m.pos, 3, pmin, pmax);

    // The original: one .bin with positions, normals, uvs, indices.
    {
        const std::string bin = bytes_of(m.pos) + bytes_of(m.nrm) + bytes_of(m.uv) + bytes_of(m.idx);
        write(dir + "/original.bin", bin);
        const size_t o1 = nv * 12, o2 = o1 + nv * 12, o3 = o2 + nv * 8;
        std::ostringstream j;
        j << R"({"asset":{"version":"2.0","generator":"scripts/make_compressed_gltf.cpp"},"scene":0,)"
          << R"("scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)"
          << R"("materials":[{"pbrMetallicRoughness":{"baseColorFactor":[0.8,0.5,0.3,1],"metallicFactor":0}}],)"
          << R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2},"indices":3,)"
          << R"("material":0}]}],"accessors":[)"
          << R"({"bufferView":0,"componentType":5126,"count":)" << nv << R"(,"type":"VEC3","min":)" << pmin
          << R"(,"max":)" << pmax << "},"
          << R"({"bufferView":1,"componentType":5126,"count":)" << nv << R"(,"type":"VEC3"},)"
          << R"({"bufferView":2,"componentType":5126,"count":)" << nv << R"(,"type":"VEC2"},)"
          << R"({"bufferView":3,"componentType":5125,"count":)" << m.idx.size() << R"(,"type":"SCALAR"}],)"
          << R"("bufferViews":[)"
          << R"({"buffer":0,"byteOffset":0,"byteLength":)" << o1 << R"(,"target":34962},)"
          << R"({"buffer":0,"byteOffset":)" << o1 << R"(,"byteLength":)" << nv * 12 << R"(,"target":34962},)"
          << R"({"buffer":0,"byteOffset":)" << o2 << R"(,"byteLength":)" << nv * 8 << R"(,"target":34962},)"
          << R"({"buffer":0,"byteOffset":)" << o3 << R"(,"byteLength":)" << m.idx.size() * 4 << R"(,"target":34963}],)"
          << R"("buffers":[{"uri":"original.bin","byteLength":)" << bin.size() << "}]}\n";
        write(dir + "/original.gltf", j.str());
    }

    // Draco: positions quantized to 14 bits, normals 10, uvs 12 (the encoder's usual settings).
    draco::Mesh dm;
    dm.set_num_points(uint32_t(nv));
    auto add = [&](draco::GeometryAttribute::Type type, const std::vector<float>& v, int n) {
        draco::GeometryAttribute ga;
        ga.Init(type, nullptr, int8_t(n), draco::DT_FLOAT32, false, int64_t(n) * 4, 0);
        const int id = dm.AddAttribute(ga, true, uint32_t(nv));
        for (size_t i = 0; i < nv; ++i)
            dm.attribute(id)->SetAttributeValue(draco::AttributeValueIndex(uint32_t(i)), &v[i * size_t(n)]);
        return dm.attribute(id)->unique_id();
    };
    const uint32_t pos_id = add(draco::GeometryAttribute::POSITION, m.pos, 3);
    const uint32_t nrm_id = add(draco::GeometryAttribute::NORMAL, m.nrm, 3);
    const uint32_t uv_id = add(draco::GeometryAttribute::TEX_COORD, m.uv, 2);
    for (size_t f = 0; f < m.idx.size() / 3; ++f)
        dm.AddFace({draco::PointIndex(m.idx[3 * f]), draco::PointIndex(m.idx[3 * f + 1]),
                    draco::PointIndex(m.idx[3 * f + 2])});
    draco::Encoder enc;
    enc.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 14);
    enc.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, 10);
    enc.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, 12);
    enc.SetSpeedOptions(5, 5);
    draco::EncoderBuffer eb;
    const draco::Status st = enc.EncodeMeshToBuffer(dm, &eb);
    if (!st.ok()) {
        std::fprintf(stderr, "draco: %s\n", st.error_msg());
        return 1;
    }
    const std::string stream(eb.data(), eb.size());
    write(dir + "/draco.bin", stream);
    std::ostringstream j;
    j << R"({"asset":{"version":"2.0","generator":"scripts/make_compressed_gltf.cpp"},"scene":0,)"
      << R"("extensionsUsed":["KHR_draco_mesh_compression"],"extensionsRequired":["KHR_draco_mesh_compression"],)"
      << R"("scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)"
      << R"("materials":[{"pbrMetallicRoughness":{"baseColorFactor":[0.8,0.5,0.3,1],"metallicFactor":0}}],)"
      << R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2},"indices":3,)"
      << R"("material":0,"extensions":{"KHR_draco_mesh_compression":{"bufferView":0,"attributes":{"POSITION":)"
      << pos_id << R"(,"NORMAL":)" << nrm_id << R"(,"TEXCOORD_0":)" << uv_id << "}}}}]}],"
      << R"("accessors":[)"
      << R"({"componentType":5126,"count":)" << nv << R"(,"type":"VEC3","min":)" << pmin << R"(,"max":)" << pmax << "},"
      << R"({"componentType":5126,"count":)" << nv << R"(,"type":"VEC3"},)"
      << R"({"componentType":5126,"count":)" << nv << R"(,"type":"VEC2"},)"
      << R"({"componentType":5125,"count":)" << m.idx.size() << R"(,"type":"SCALAR"}],)"
      << R"("bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":)" << stream.size() << "}],"
      << R"("buffers":[{"uri":"draco.bin","byteLength":)" << stream.size() << "}]}\n";
    write(dir + "/draco.gltf", j.str());
    std::printf("wrote %s/original.gltf (%zu vertices, %zu triangles) and draco.gltf (%zu-byte stream)\n", dir.c_str(),
                nv, m.idx.size() / 3, stream.size());
    return 0;
}
