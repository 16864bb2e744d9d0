#include "scene/mitsuba3_syntax.h"

#include <cctype>
#include <cmath>
#include <map>

#include "util/error.h"

namespace lt {

namespace {

// Where 0.6 does not spell a property as the camelCase of its Mitsuba 3 name.
const std::map<std::string, std::string> Mitsuba3Renames = {
    {"int_ior", "intIOR"}, // dielectrics and plastics
    {"ext_ior", "extIOR"},
    {"sample_border", "highQualityEdges"}, // films
};

int leadingNumber(const std::string& s, size_t& pos) {
    const size_t start = pos;
    int v = 0;
    while (pos < s.size() && std::isdigit(static_cast<unsigned char>(s[pos])) && pos - start < 4)
        v = 10 * v + (s[pos++] - '0');
    return pos == start ? -1 : v;
}

} // namespace

SceneSyntax sceneSyntaxOfVersion(const std::string& version) {
    if (version.empty()) return SceneSyntax::Mitsuba06;
    size_t pos = 0;
    const int major = leadingNumber(version, pos);
    int minor = -1;
    if (pos < version.size() && version[pos] == '.') minor = leadingNumber(version, ++pos);
    if (major == 0 && minor >= 4 && minor <= 6) return SceneSyntax::Mitsuba06;
    if ((major == 2 || major == 3) && minor >= 0) return SceneSyntax::Mitsuba3;
    throw Error("version \"" + version +
                "\" is not one lt reads (Mitsuba 0.4 to 0.6, 2.x and 3.x; older files upgrade with Mitsuba 0.6's "
                "mtsgui)");
}

std::string mitsuba3PropertyName(const std::string& name) {
    if (auto it = Mitsuba3Renames.find(name); it != Mitsuba3Renames.end()) return it->second;
    std::string out;
    bool upper = false;
    for (char c : name) {
        if (c == '_' && !out.empty()) {
            upper = true;
            continue;
        }
        out += upper ? char(std::toupper(static_cast<unsigned char>(c))) : c;
        upper = false;
    }
    return out;
}

std::string mitsuba3Spelling(const std::string& name06) {
    for (const auto& [name3, name] : Mitsuba3Renames)
        if (name == name06) return name3;
    // Mitsuba 3's camel_to_underscore_case: an underscore before a capital that follows a lower-case
    // letter, every capital lowered.
    std::string out;
    for (size_t i = 0; i < name06.size(); ++i) {
        const auto c = static_cast<unsigned char>(name06[i]);
        if (std::isupper(c) && i > 0 && std::islower(static_cast<unsigned char>(name06[i - 1]))) out += '_';
        out += char(std::tolower(c));
    }
    return out;
}

std::string mitsuba3PropertyTag(const std::string& tag) { return tag == "int" ? "integer" : tag; }

void translateMitsuba3Plugin(SceneObject& o) {
    auto add = [&](const std::string& key, Property p) {
        p.name = key + " (Mitsuba 3's default)";
        p.line = o.line;
        o.props.emplace(key, std::move(p));
    };
    // Mitsuba 3's sunsky (3.6 and later) pairs the sky with another sun model and its own units: reading it
    // as 0.6's would render a different daylight without a word.
    if (o.tag == "emitter" && (o.type == "sunsky" || o.type == "sun" || o.type == "sky"))
        o.fail("Mitsuba 3's " + o.type +
               " is not Mitsuba 0.6's (another sun model and scale); lt reads 0.6's: "
               "write the scene's daylight in a version=\"0.6.0\" file and include it");
    if (o.tag == "bsdf" && (o.type == "conductor" || o.type == "roughconductor") && !o.has("material")) {
        if (!o.has("eta") && !o.has("k")) {
            Property p;
            p.type = Property::Type::String;
            p.string = "none";
            add("material", p);
        } else {
            for (const auto& [key, value] : {std::pair{"eta", 0.0}, std::pair{"k", 1.0}})
                if (!o.has(key)) {
                    Property p;
                    p.type = Property::Type::Spectrum;
                    p.spectrum = Spectrum(value);
                    add(key, p);
                }
        }
    }
    if (o.tag == "texture" && o.type == "bitmap" && o.has("raw") && o.getBoolean("raw")) {
        Property p;
        p.number = 1.0;
        add("gamma", p);
    }
    if (o.tag == "texture") {
        if (o.has("toUv")) {
            const Transform t = o.getTransform("toUv");
            const Matrix4& m = t.matrix();
            // uv' = M (u, v, 0, 1): only M's u and v columns and its translation act; they must not mix u and v.
            if (std::abs(m.m[0][1]) > 0 || std::abs(m.m[1][0]) > 0)
                o.fail("to_uv must scale and translate u and v only (Mitsuba 0.6's uscale, vscale, uoffset, "
                       "voffset); this one rotates or shears");
            const std::pair<const char*, double> uv[] = {
                {"uscale", m.m[0][0]}, {"vscale", m.m[1][1]}, {"uoffset", m.m[0][3]}, {"voffset", m.m[1][3]}};
            for (const auto& [key, value] : uv) {
                if (o.has(key)) o.fail(std::string("give to_uv or ") + key + ", not both");
                Property p;
                p.number = value;
                add(key, p);
            }
        }
    }
}

} // namespace lt
