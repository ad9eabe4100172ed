// SPDX-License-Identifier: Apache-2.0
// OBJ with its MTL: the input is "<obj text>\n#--MTL--\n<mtl text>"; the OBJ may name the
// material library "mesh.mtl" (the seeds do).
#include "FuzzSupport.h"
#include "vdbmap/io/MeshIO.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace vdbmap;
    const auto parts = fuzz::splitInput(fuzz::asText(data, size), "\n#--MTL--\n");
    fuzz::writeInput("mesh.mtl", parts.size() > 1 ? parts[1] : std::string_view());
    const auto path = fuzz::writeInput("mesh.obj", parts[0]);
    fuzz::refusesOnlyWithTypedErrors([&] {
        const ObjMesh mesh = readObj(path);
        for (const auto& t : mesh.triangles) {  // the reader promises valid indices
            for (int k = 0; k < 3; ++k) {
                if (t.v[k] >= mesh.positions.size()) std::abort();
                if (!mesh.uvs.empty() && t.vt[k] >= mesh.uvs.size()) std::abort();
            }
            if (!mesh.materials.empty() && t.material >= mesh.materials.size()) std::abort();
        }
    });
    return 0;
}
