// Mitsuba XML -> SceneObject tree (see scene_object.h). pugixml does the XML; this file knows Mitsuba's
// element vocabulary: properties, transforms, nested objects, ref, include, default. A 2.x/3.x file's names
// are translated to 0.6's as they are read (mitsuba3_syntax.h).
#include <pugixml.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "util/error.h"
#include "util/number_text.h"
#include "scene/missing_file.h"
#include "scene/mitsuba3_syntax.h"
#include "scene/scene_object.h"

namespace lt {

namespace {

namespace fs = std::filesystem;

const std::set<std::string> ObjectTags = {"shape", "bsdf", "texture", "emitter", "sensor",
                                          "film",  "rfilter", "sampler", "integrator"};
// Mitsuba elements we recognise but do not implement: a clear error beats "unknown element".
const std::set<std::string> UnsupportedTags = {"medium", "phase", "subsurface", "volume", "blackbody", "animation"};

struct Source {
    std::string file;
    SceneSyntax syntax = SceneSyntax::Mitsuba06; // from the root's version attribute
    std::string text;
    std::vector<size_t> lineStarts;
    int lineOf(ptrdiff_t offset) const {
        if (offset < 0) return 0;
        return 1 + int(std::upper_bound(lineStarts.begin(), lineStarts.end(), size_t(offset)) - lineStarts.begin());
    }
};

class Parser {
public:
    explicit Parser(std::map<std::string, std::string> params) : params_(std::move(params)) {}

    XmlDocument parse(const std::string& filename) {
        XmlDocument doc;
        auto root = std::make_shared<SceneObject>();
        root->tag = "scene";
        root->file = filename;
        parseFile(filename, *root, true);
        doc.root = root;
        doc.filesRead = filesRead_;
        return doc;
    }

private:
    std::map<std::string, std::string> params_;
    std::map<std::string, std::shared_ptr<const SceneObject>> ids_;
    std::vector<std::string> filesRead_;
    std::vector<std::string> includeStack_;
    std::vector<std::unique_ptr<Source>> sources_;

    Source& load(const std::string& filename) {
        std::ifstream in(filename, std::ios::binary);
        if (!in) throw Error(filename + ": cannot open scene file" + didYouMean(filename));
        auto src = std::make_unique<Source>();
        src->file = filename;
        std::ostringstream ss;
        ss << in.rdbuf();
        src->text = ss.str();
        for (size_t i = 0; i < src->text.size(); ++i)
            if (src->text[i] == '\n') src->lineStarts.push_back(i);
        sources_.push_back(std::move(src));
        filesRead_.push_back(filename);
        return *sources_.back();
    }

    void parseFile(const std::string& filename, SceneObject& scene, bool isMain) {
        const std::string canonical = fs::weakly_canonical(filename).string();
        if (std::find(includeStack_.begin(), includeStack_.end(), canonical) != includeStack_.end())
            throw Error(filename + ": include cycle");
        Source& src = load(filename);
        pugi::xml_document xml;
        const pugi::xml_parse_result res = xml.load_buffer(src.text.data(), src.text.size());
        if (!res)
            throw Error(filename + ':' + std::to_string(src.lineOf(res.offset)) + ": malformed XML: " + res.description());
        const pugi::xml_node root = xml.document_element();
        if (std::string(root.name()) != "scene")
            throw Error(filename + ':' + std::to_string(src.lineOf(root.offset_debug())) +
                        ": the root element must be <scene>, not <" + root.name() + ">");
        try {
            src.syntax = sceneSyntaxOfVersion(root.attribute("version").value());
        } catch (const Error& e) {
            fail(src, root, e.what());
        }
        if (isMain) scene.line = src.lineOf(root.offset_debug());
        includeStack_.push_back(canonical);
        // <default> values first, wherever they stand: they apply to the whole file (Mitsuba 0.6).
        for (const pugi::xml_node& c : root.children("default")) {
            const std::string name = c.attribute("name").value();
            if (name.empty()) throw Error(filename + ':' + std::to_string(src.lineOf(c.offset_debug())) +
                                          ": <default> needs a name");
            params_.try_emplace(name, c.attribute("value").value());
        }
        for (const pugi::xml_node& c : root.children()) parseChild(c, scene, src);
        includeStack_.pop_back();
    }

    [[noreturn]] void fail(const Source& src, const pugi::xml_node& node, const std::string& message) const {
        throw Error(src.file + ':' + std::to_string(src.lineOf(node.offset_debug())) + ": <" + node.name() + ">: " +
                    message);
    }

    // Attribute with $name substitution.
    std::string attr(const Source& src, const pugi::xml_node& node, const char* name, bool required = false) const {
        const pugi::xml_attribute a = node.attribute(name);
        if (!a) {
            if (required) fail(src, node, std::string("missing attribute '") + name + "'");
            return {};
        }
        std::string v = a.value();
        size_t pos = 0;
        while ((pos = v.find('$', pos)) != std::string::npos) {
            size_t end = pos + 1;
            while (end < v.size() && (std::isalnum(static_cast<unsigned char>(v[end])) || v[end] == '_')) ++end;
            const std::string key = v.substr(pos + 1, end - pos - 1);
            auto it = params_.find(key);
            if (key.empty() || it == params_.end())
                fail(src, node, "undefined parameter '$" + key + "' (give it with <default> or on the command line)");
            v.replace(pos, end - pos, it->second);
            pos += it->second.size();
        }
        return v;
    }

    static std::vector<std::string> splitList(const std::string& s) {
        std::vector<std::string> out;
        std::string cur;
        for (char c : s) {
            if (c == ',' || std::isspace(static_cast<unsigned char>(c))) {
                if (!cur.empty()) out.push_back(cur);
                cur.clear();
            } else {
                cur += c;
            }
        }
        if (!cur.empty()) out.push_back(cur);
        return out;
    }

    double number(const Source& src, const pugi::xml_node& node, const std::string& text) const {
        const std::optional<double> v = numberFromText(text);
        if (!v) fail(src, node, "'" + text + "' is not a number");
        if (!std::isfinite(*v)) fail(src, node, "'" + text + "' is not a finite number");
        return *v;
    }

    std::vector<double> numbers(const Source& src, const pugi::xml_node& node, const std::string& text) const {
        std::vector<double> out;
        for (const auto& tok : splitList(text)) out.push_back(number(src, node, tok));
        return out;
    }

    Vec3 vec3Attr(const Source& src, const pugi::xml_node& node, const char* name, std::optional<Vec3> def) const {
        const std::string s = attr(src, node, name);
        if (s.empty()) {
            if (def) return *def;
            fail(src, node, std::string("missing attribute '") + name + "'");
        }
        const auto v = numbers(src, node, s);
        if (v.size() != 3) fail(src, node, std::string("attribute '") + name + "' needs 3 numbers");
        return {v[0], v[1], v[2]};
    }

    // x, y, z attributes (each default 0), or value="x y z".
    Vec3 xyz(const Source& src, const pugi::xml_node& node, double def) const {
        if (node.attribute("value")) {
            const auto v = numbers(src, node, attr(src, node, "value"));
            if (v.size() == 1) return {v[0], v[0], v[0]};
            if (v.size() != 3) fail(src, node, "value needs 1 or 3 numbers");
            return {v[0], v[1], v[2]};
        }
        Vec3 r{def, def, def};
        const char* names[3] = {"x", "y", "z"};
        for (int i = 0; i < 3; ++i)
            if (node.attribute(names[i])) r[i] = number(src, node, attr(src, node, names[i]));
        return r;
    }

    static double srgbToLinear(double v) {
        return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
    }

    Spectrum color(const Source& src, const pugi::xml_node& node, bool srgbEncoded) const {
        const std::string v = attr(src, node, "value", true);
        Spectrum s;
        if (!v.empty() && v[0] == '#') {
            // "#rrggbb" is always sRGB-encoded (Mitsuba).
            if (v.size() != 7) fail(src, node, "'" + v + "' is not a #rrggbb colour");
            for (int i = 0; i < 3; ++i) {
                unsigned c = 0;
                const auto [p, ec] = std::from_chars(v.data() + 1 + 2 * i, v.data() + 3 + 2 * i, c, 16);
                if (ec != std::errc() || p != v.data() + 3 + 2 * i) fail(src, node, "'" + v + "' is not a #rrggbb colour");
                s[i] = srgbToLinear(c / 255.0);
            }
            return s;
        }
        const auto n = numbers(src, node, v);
        if (n.size() == 1) s = Spectrum(n[0]);
        else if (n.size() == 3) s = {n[0], n[1], n[2]};
        else fail(src, node, "'" + v + "' needs 1 or 3 numbers");
        if (srgbEncoded)
            for (int i = 0; i < 3; ++i) s[i] = srgbToLinear(s[i]);
        return s;
    }

    Spectrum spectrum(const Source& src, const pugi::xml_node& node) const {
        const std::string v = attr(src, node, "value");
        if (v.empty()) {
            if (node.attribute("filename")) fail(src, node, "spectra from files are not supported; give wavelength:value pairs");
            fail(src, node, "missing attribute 'value'");
        }
        if (v.find(':') == std::string::npos) {
            const auto n = numbers(src, node, v);
            if (n.size() == 1) return Spectrum(n[0]);
            if (n.size() == 3) return {n[0], n[1], n[2]};
            fail(src, node, "'" + v + "' is neither one value nor a list of wavelength:value pairs");
        }
        std::vector<std::pair<double, double>> samples;
        for (const auto& tok : splitList(v)) {
            const size_t colon = tok.find(':');
            if (colon == std::string::npos) fail(src, node, "'" + tok + "' is not a wavelength:value pair");
            samples.emplace_back(number(src, node, tok.substr(0, colon)), number(src, node, tok.substr(colon + 1)));
        }
        try {
            return spectrumToRgb(samples);
        } catch (const Error& e) {
            fail(src, node, e.what());
        }
    }

    Transform transform(const Source& src, const pugi::xml_node& node) const {
        Transform t;
        for (const pugi::xml_node& op : node.children()) {
            if (op.type() != pugi::node_element) continue;
            const std::string name = op.name();
            Transform m;
            try {
                if (name == "matrix") {
                    const auto v = numbers(src, op, attr(src, op, "value", true));
                    Matrix4 mat = Matrix4::identity();
                    if (v.size() == 16) {
                        for (int i = 0; i < 16; ++i) mat.m[i / 4][i % 4] = v[i];
                    } else if (v.size() == 9) {
                        for (int i = 0; i < 9; ++i) mat.m[i / 3][i % 3] = v[i];
                    } else {
                        fail(src, op, "matrix needs 16 (or 9) numbers, got " + std::to_string(v.size()));
                    }
                    m = Transform::fromMatrix(mat);
                } else if (name == "translate") {
                    m = Transform::translate(xyz(src, op, 0));
                } else if (name == "scale") {
                    m = Transform::scale(xyz(src, op, 1));
                } else if (name == "rotate") {
                    const Vec3 axis = xyz(src, op, 0);
                    m = Transform::rotate(axis, number(src, op, attr(src, op, "angle", true)));
                } else if (name == "lookat" || name == "lookAt") {
                    m = Transform::lookAt(vec3Attr(src, op, "origin", {}), vec3Attr(src, op, "target", {}),
                                          vec3Attr(src, op, "up", Vec3(0, 1, 0)));
                } else {
                    fail(src, op, "unknown transform operation (expected matrix, lookat, rotate, translate or scale)");
                }
            } catch (const Error& e) {
                const std::string what = e.what();
                if (what.rfind(src.file, 0) == 0) throw;
                fail(src, op, what);
            }
            // Mitsuba applies the operations in document order: each new one composes on the left.
            t = m * t;
        }
        return t;
    }

    void addProperty(const Source& src, const pugi::xml_node& node, SceneObject& owner) {
        const std::string tag = propertyTag(src, node);
        const std::string written = attr(src, node, "name", true);
        const std::string name = nameAttr(src, node, true);
        Property p;
        p.name = written;
        p.line = src.lineOf(node.offset_debug());
        if (tag == "float") {
            p.type = Property::Type::Float;
            p.number = number(src, node, attr(src, node, "value", true));
        } else if (tag == "integer") {
            p.type = Property::Type::Integer;
            const std::string v = attr(src, node, "value", true);
            long long i = 0;
            const auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), i);
            if (ec != std::errc() || ptr != v.data() + v.size() || v.empty())
                fail(src, node, "'" + v + "' is not an integer");
            p.number = double(i);
        } else if (tag == "boolean") {
            p.type = Property::Type::Boolean;
            const std::string v = attr(src, node, "value", true);
            if (v == "true") p.boolean = true;
            else if (v == "false") p.boolean = false;
            else fail(src, node, "'" + v + "' is not a boolean (true or false)");
        } else if (tag == "string") {
            p.type = Property::Type::String;
            p.string = attr(src, node, "value", true);
        } else if (tag == "rgb" || tag == "srgb") {
            p.type = Property::Type::Spectrum;
            p.spectrum = color(src, node, tag == "srgb");
        } else if (tag == "spectrum") {
            p.type = Property::Type::Spectrum;
            p.spectrum = spectrum(src, node);
        } else if (tag == "point" || tag == "vector") {
            p.type = tag == "point" ? Property::Type::Point : Property::Type::Vector;
            p.vector = xyz(src, node, 0);
        } else if (tag == "transform") {
            p.type = Property::Type::Transform;
            p.transform = transform(src, node);
        }
        if (owner.props.count(name)) fail(src, node, "property '" + name + "' is given twice");
        owner.props.emplace(name, std::move(p));
    }

    // A property's tag in 0.6's vocabulary, and a property's or named object's name.
    static std::string propertyTag(const Source& src, const pugi::xml_node& node) {
        return src.syntax == SceneSyntax::Mitsuba3 ? mitsuba3PropertyTag(node.name()) : node.name();
    }
    // (An object's name at scene level is free-form in 3.x files; `atSceneLevel` leaves it as written.)
    std::string nameAttr(const Source& src, const pugi::xml_node& node, bool required = false,
                         bool atSceneLevel = false) const {
        const std::string written = attr(src, node, "name", required);
        if (src.syntax != SceneSyntax::Mitsuba3 || atSceneLevel) return written;
        // A 0.6 name in a 3.x file means nothing to Mitsuba 3 (it refuses the file); taking it with its 0.6
        // meaning would hide a scene that does not render as its author saw it.
        if (std::any_of(written.begin(), written.end(),
                        [](char c) { return std::isupper(static_cast<unsigned char>(c)); }))
            fail(src, node,
                 "'" + written + "' is Mitsuba 0.6 spelling, but this file declares a 3.x version (write '" +
                     mitsuba3Spelling(written) + "')");
        return mitsuba3PropertyName(written);
    }

    // Objects nest a few levels in real scenes (shape > bsdf > bsdf > texture); a limit keeps a malicious or
    // broken file from exhausting the stack in this recursion (and in the tree's destruction).
    static constexpr int MaxNesting = 64;

    void parseChild(const pugi::xml_node& node, SceneObject& owner, const Source& src, int depth = 1) {
        if (node.type() != pugi::node_element) return;
        if (depth > MaxNesting)
            fail(src, node, "elements nested deeper than " + std::to_string(MaxNesting) + " levels");
        const std::string tag = propertyTag(src, node);
        static const std::set<std::string> PropertyTags = {"float", "integer", "boolean", "string", "rgb",
                                                           "srgb",  "spectrum", "point", "vector", "transform"};
        if (PropertyTags.count(tag)) {
            addProperty(src, node, owner);
        } else if (ObjectTags.count(tag)) {
            auto obj = std::make_shared<SceneObject>();
            obj->tag = tag;
            obj->type = attr(src, node, "type");
            obj->id = attr(src, node, "id");
            obj->name = nameAttr(src, node, false, owner.tag == "scene");
            obj->file = src.file;
            obj->line = src.lineOf(node.offset_debug());
            obj->syntax = src.syntax;
            if (obj->type.empty()) fail(src, node, "missing attribute 'type'");
            for (const pugi::xml_node& c : node.children())
                parseChild(c, *obj, src, depth + 1);
            if (src.syntax == SceneSyntax::Mitsuba3) translateMitsuba3Plugin(*obj);
            if (!obj->id.empty()) {
                if (ids_.count(obj->id)) fail(src, node, "id '" + obj->id + "' is already defined");
                ids_[obj->id] = obj;
            }
            owner.children.push_back(obj);
        } else if (tag == "ref") {
            const std::string id = attr(src, node, "id", true);
            auto it = ids_.find(id);
            if (it == ids_.end()) fail(src, node, "reference to undefined id '" + id + "'");
            const std::string name = nameAttr(src, node);
            if (!name.empty() && name != it->second->name) {
                // A named reference (e.g. a texture used as "reflectance"): a renamed alias of the object.
                auto alias = std::make_shared<SceneObject>(*it->second);
                alias->name = name;
                alias->original = it->second->declaration();
                owner.children.push_back(alias);
            } else {
                owner.children.push_back(it->second);
            }
        } else if (tag == "include") {
            if (owner.tag != "scene") fail(src, node, "<include> is only allowed directly inside <scene>");
            fs::path p = attr(src, node, "filename", true);
            if (p.is_relative()) p = fs::path(src.file).parent_path() / p;
            parseFile(p.string(), owner, false);
        } else if (tag == "default") {
            if (owner.tag != "scene") fail(src, node, "<default> is only allowed directly inside <scene>");
        } else if (tag == "null") {
            // Mitsuba 0.6 allows <null name="..."/> to unset an inherited property: nothing to do here.
        } else if (UnsupportedTags.count(tag)) {
            fail(src, node, "not supported by lt (surfaces only: no participating media, subsurface or animation)");
        } else {
            fail(src, node, "unknown element");
        }
    }
};

} // namespace

XmlDocument parseSceneXml(const std::string& filename, const std::map<std::string, std::string>& parameters) {
    Parser parser(parameters);
    return parser.parse(filename);
}

} // namespace lt
