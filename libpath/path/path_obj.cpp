#include "path/path_obj.h"

#include <fstream>

#include "util/error.h"
#include "util/temp_output.h"

namespace lt {

void writePathsObj(const std::string& objPath, std::span<const file::PathRecord> paths, const std::string& source) {
    TempOutput temp(objPath);
    std::ofstream out(temp.path());
    if (!out) throw Error(objPath + ": cannot create " + temp.path());
    out.precision(9); // positions are doubles; 9 digits keep float-level detail at any scene scale
    out << "# " << paths.size() << " light paths from " << source << ", light-to-eye order\n";
    size_t next = 1; // OBJ vertex indices are 1-based and global over the file
    for (size_t i = 0; i < paths.size(); ++i) {
        const auto& p = paths[i];
        out << "o path_" << i << "_s" << p.s << "_t" << p.t << '\n';
        for (const auto& v : p.vertices)
            out << "v " << v.p[0] << ' ' << v.p[1] << ' ' << v.p[2] << '\n';
        if (p.vertices.size() >= 2) {
            out << 'l';
            for (size_t k = 0; k < p.vertices.size(); ++k)
                out << ' ' << next + k;
            out << '\n';
        }
        next += p.vertices.size();
    }
    out.close();
    if (!out) throw Error(objPath + ": cannot write " + temp.path());
    temp.commit();
}

} // namespace lt
