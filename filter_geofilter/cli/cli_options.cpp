#include "cli_options.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

namespace geofilter::cli {

namespace {

// Set by the tool itself from --select-*, so it has no option of its own.
bool has_own_option(const ParameterSpec& p) { return p.name != param::use_selection; }

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

std::string preset_names() {
    std::string names;
    for (const auto& f : filter_table()) names += (names.empty() ? "" : ", ") + f.cli_name;
    return names;
}

// The parameter an option names, searched over every filter so that an option of another
// preset gets "does not apply" rather than "unknown".
const ParameterSpec* any_parameter_for(const std::string& option) {
    for (const auto& f : filter_table())
        for (const auto& p : f.parameters)
            if (has_own_option(p) && (option_for(p.name) == option || "--" + p.name == option)) return &p;
    return nullptr;
}

double parse_number(const std::string& option, std::string text) {
    const std::string original = text;
    if (!text.empty() && text[0] == '+') text.erase(0, 1);  // from_chars refuses the sign
    double v = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size())
        throw UsageError(option + " wants a number, got '" + original + "'");
    if (!std::isfinite(v)) throw UsageError(option + " wants a finite number, got '" + original + "'");
    return v;
}

std::vector<double> parse_list(const std::string& option, const std::string& text, size_t min_count, size_t max_count,
                               const std::string& form) {
    std::vector<double> out;
    size_t start = 0;
    while (true) {
        const size_t comma = text.find(',', start);
        out.push_back(parse_number(option, text.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    if (out.size() < min_count || out.size() > max_count)
        throw UsageError(option + " wants " + form + " (comma-separated, no spaces), got '" + text + "'");
    return out;
}

// The words that may name an enum choice: the first word of its label and that word's
// hyphenated parts ("Jacobi-PCG (paper)" -> jacobi-pcg, jacobi, pcg).
std::vector<std::set<std::string>> choice_words(const ParameterSpec& p) {
    std::vector<std::set<std::string>> words;
    for (const auto& label : p.choices) {
        const std::string first = lower(label.substr(0, label.find(' ')));
        std::set<std::string> w{first};
        std::istringstream parts(first);
        for (std::string part; std::getline(parts, part, '-');)
            if (!part.empty()) w.insert(part);
        words.push_back(w);
    }
    return words;
}

double parse_parameter(const std::string& option, const ParameterSpec& p, const std::string& text) {
    switch (p.type) {
    case ParameterType::Float: return parse_number(option, text);
    case ParameterType::Length: {
        const double v = parse_number(option, text);
        if (v < 0) throw UsageError(option + " must be a length >= 0, got '" + text + "'");
        return v;
    }
    case ParameterType::Int: {
        const double v = parse_number(option, text);
        if (v != std::floor(v)) throw UsageError(option + " wants a whole number, got '" + text + "'");
        return v;
    }
    case ParameterType::Bool: {
        const std::string t = lower(text);
        if (t == "1" || t == "true" || t == "yes" || t == "on") return 1;
        if (t == "0" || t == "false" || t == "no" || t == "off") return 0;
        throw UsageError(option + " wants yes or no, got '" + text + "'");
    }
    case ParameterType::Enum: {
        const std::string t = lower(text);
        const auto words = choice_words(p);
        for (size_t i = 0; i < words.size(); ++i)
            if (t == lower(p.choices[i]) || t == std::to_string(i)) return double(i);
        std::vector<size_t> matches;
        for (size_t i = 0; i < words.size(); ++i)
            if (words[i].count(t)) matches.push_back(i);
        if (matches.size() == 1) return double(matches[0]);
        std::string list;
        for (const auto& k : choice_keywords(p)) list += (list.empty() ? "" : ", ") + k;
        throw UsageError(option + " wants one of " + list + ", got '" + text + "'");
    }
    }
    return 0;
}

struct Token {
    std::string option;               // "--s1", or empty for a positional argument
    std::optional<std::string> value;
};

// Tool options that are not table parameters. `repeatable` ones collect every use.
struct ToolOption {
    const char* name;
    bool takes_value;
    bool repeatable;
};
const ToolOption tool_options[] = {
    {"--help", false, false},          {"--quiet", false, false},        {"--overwrite-input", false, false},
    {"--plot", true, false},           {"--select-sphere", true, true},
    {"--select-box", true, true},      {"--select-stored", false, false}, {"--zeros", true, false},
    {"--poles", true, false},
};

const ToolOption* tool_option(const std::string& name) {
    for (const auto& o : tool_options)
        if (name == o.name) return &o;
    return nullptr;
}

std::vector<Token> tokenize(const std::vector<std::string>& args) {
    std::vector<Token> tokens;
    bool options_ended = false;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (options_ended || a.size() < 2 || a[0] != '-') {
            tokens.push_back({"", a});
            continue;
        }
        if (a == "--") {
            options_ended = true;
            continue;
        }
        std::string name = a;
        std::optional<std::string> value;
        if (a == "-h") name = "--help";
        else if (a == "-q") name = "--quiet";
        else if (a.rfind("--", 0) != 0) throw UsageError("unknown option " + a + " (see geofilter --help)");
        const size_t eq = name.find('=');
        if (eq != std::string::npos) {
            value = name.substr(eq + 1);
            name = name.substr(0, eq);
        }
        const ToolOption* tool = tool_option(name);
        const ParameterSpec* p = any_parameter_for(name);
        bool no_prefixed_bool = false;
        if (!tool && !p && name.rfind("--no-", 0) == 0) {
            p = any_parameter_for("--" + name.substr(5));
            no_prefixed_bool = p && p->type == ParameterType::Bool;
            if (!no_prefixed_bool) p = nullptr;
        }
        if (!tool && !p) throw UsageError("unknown option " + name + " (see geofilter --help)");
        const bool takes_value = tool ? tool->takes_value : p->type != ParameterType::Bool;
        if (no_prefixed_bool) {
            if (value) throw UsageError(name + " takes no value");
            tokens.push_back({"--" + name.substr(5), std::string("no")});
            continue;
        }
        if (takes_value && !value) {
            if (i + 1 >= args.size()) throw UsageError(name + " needs a value");
            value = args[++i];
        }
        if (!takes_value && value && tool) throw UsageError(name + " takes no value");
        if (!takes_value && !value && p) value = "yes";
        tokens.push_back({name, value});
    }
    return tokens;
}

// Strips the HTML the table's descriptions may carry (MeshLab shows them as rich text).
std::string plain_text(const std::string& html) {
    std::string out;
    for (size_t i = 0; i < html.size(); ++i) {
        // Only what looks like a tag: "s < s1" in a help text is prose.
        const bool tag_start = html[i] == '<' && i + 1 < html.size() &&
                               (std::isalpha(static_cast<unsigned char>(html[i + 1])) || html[i + 1] == '/');
        if (tag_start) {
            const size_t close = html.find('>', i);
            if (close != std::string::npos) {
                i = close;
                continue;
            }
        }
        out += html[i];
    }
    for (const auto& [entity, text] : std::map<std::string, std::string>{{"&amp;", "&"}, {"&lt;", "<"}, {"&gt;", ">"}}) {
        for (size_t at; (at = out.find(entity)) != std::string::npos;) out.replace(at, entity.size(), text);
    }
    return out;
}

// Word-wraps `text` with every line indented by `indent`; the first line starts with
// `first_line` instead of blanks when given (a list item's name).
std::string wrap(const std::string& text, size_t indent, const std::string& first_line = "", size_t width = 80) {
    std::istringstream words(text);
    std::string out = first_line.empty() ? std::string(indent, ' ') : first_line, word;
    if (out.size() < indent) out.resize(indent, ' ');
    size_t column = out.size();
    bool first = true;
    while (words >> word) {
        if (!first && column + 1 + word.size() > width) {
            out += "\n" + std::string(indent, ' ');
            column = indent;
            first = true;
        }
        if (!first) {
            out += ' ';
            ++column;
        }
        out += word;
        column += word.size();
        first = false;
    }
    return out + "\n";
}

// "Removes features ... (paper Fig. 12). Second-order ..." -> the part before the first
// ". X" (a full stop followed by a capital), so that "eq. 16" does not end it.
std::string first_sentence(const std::string& text) {
    for (size_t i = 0; i + 2 < text.size(); ++i)
        if (text[i] == '.' && text[i + 1] == ' ' && std::isupper(static_cast<unsigned char>(text[i + 2])))
            return text.substr(0, i + 1);
    return text;
}

std::string default_text(const ParameterSpec& p) {
    if (p.type == ParameterType::Enum) return choice_keywords(p)[size_t(p.default_value)];
    if (p.type == ParameterType::Bool) return p.default_value != 0 ? "yes" : "no";
    if (p.type == ParameterType::Length && p.default_value != 0)
        return format_number(100 * p.default_value) + " % of the diagonal";
    return format_number(p.default_value);
}

} // namespace

std::string option_for(const std::string& name) {
    std::string out = "--";
    for (size_t i = 0; i < name.size(); ++i) {
        const unsigned char c = static_cast<unsigned char>(name[i]);
        // Only a capital inside a word starts a new one: "G0" and "Ginf" stay as the paper writes them.
        if (std::isupper(c) && i > 0 && std::islower(static_cast<unsigned char>(name[i - 1]))) {
            out += '-';
            out += char(std::tolower(c));
        } else {
            out += char(c);
        }
    }
    return out;
}

std::vector<std::string> choice_keywords(const ParameterSpec& p) {
    const auto words = choice_words(p);
    std::map<std::string, int> uses;
    for (const auto& w : words)
        for (const auto& word : w) ++uses[word];
    std::vector<std::string> keywords;
    for (size_t i = 0; i < words.size(); ++i) {
        std::string best;
        for (const auto& w : words[i])
            if (uses[w] == 1 && (best.empty() || w.size() < best.size())) best = w;
        keywords.push_back(best.empty() ? std::to_string(i) : best);
    }
    return keywords;
}

CliOptions parse_command_line(const std::vector<std::string>& args) {
    CliOptions o;
    const std::vector<Token> tokens = tokenize(args);
    std::vector<std::string> positional;
    for (const auto& t : tokens) {
        if (t.option.empty()) positional.push_back(*t.value);
        else if (t.option == "--help") o.help = true;
    }
    if (!positional.empty()) {
        o.preset = find_filter(positional[0]);
        if (!o.preset || o.preset->cli_name != positional[0])
            throw UsageError("unknown preset '" + positional[0] + "' (one of: " + preset_names() + ")");
    }
    if (o.help) return o;
    if (!o.preset) throw UsageError("no preset given: geofilter PRESET [options] INPUT OUTPUT (see geofilter --help)");
    const FilterSpec& spec = *o.preset;
    const bool measure = spec.kind == FilterKind::Measure;

    std::set<std::string> seen;
    std::map<std::string, double> set_values;
    std::vector<double> zeros, poles;
    for (const auto& t : tokens) {
        if (t.option.empty() || t.option == "--help") continue;
        const ToolOption* tool = tool_option(t.option);
        if (!(tool && tool->repeatable) && !seen.insert(t.option).second) throw UsageError(t.option + " given twice");
        const std::string& v = t.value.value_or("");
        if (t.option == "--quiet") o.quiet = true;
        else if (t.option == "--overwrite-input") o.overwrite_input = true;
        else if (t.option == "--select-stored") o.select_stored = true;
        else if (t.option == "--plot") {
            if (measure) throw UsageError("--plot draws a filter's G(s): the measure preset has none");
            o.plot = v;
        } else if (t.option == "--select-sphere") {
            const auto n = parse_list(t.option, v, 4, 4, "cx,cy,cz,r");
            if (!(n[3] > 0)) throw UsageError("--select-sphere radius must be > 0, got " + format_number(n[3]));
            o.spheres.push_back({Eigen::Vector3d(n[0], n[1], n[2]), n[3]});
        } else if (t.option == "--select-box") {
            const auto n = parse_list(t.option, v, 6, 6, "x0,y0,z0,x1,y1,z1");
            const Eigen::Vector3d a(n[0], n[1], n[2]), b(n[3], n[4], n[5]);
            o.boxes.push_back({a.cwiseMin(b), a.cwiseMax(b)});
        } else if (t.option == "--zeros" || t.option == "--poles") {
            if (!spec.parameter(param::zero_prefix + "1"))
                throw UsageError(t.option + " does not apply to the " + spec.cli_name + " preset (only to polezero)");
            (t.option == "--zeros" ? zeros : poles) =
                parse_list(t.option, v, 1, param::max_pole_zero, "1 to " + std::to_string(param::max_pole_zero) + " numbers");
        } else {
            const ParameterSpec* p = nullptr;
            for (const auto& q : spec.parameters)
                if (has_own_option(q) && (option_for(q.name) == t.option || "--" + q.name == t.option)) p = &q;
            if (!p) throw UsageError(t.option + " does not apply to the " + spec.cli_name + " preset (see geofilter " +
                                     spec.cli_name + " --help)");
            if (set_values.count(p->name)) throw UsageError(option_for(p->name) + " given twice");
            set_values[p->name] = parse_parameter(t.option, *p, v);
        }
    }
    for (const auto& [list, prefix, option] : {std::tuple{&zeros, param::zero_prefix, "--zeros"},
                                               std::tuple{&poles, param::pole_prefix, "--poles"}}) {
        if (list->empty()) continue;
        for (int i = 1; i <= param::max_pole_zero; ++i) {
            const std::string name = prefix + std::to_string(i);
            if (set_values.count(name))
                throw UsageError(std::string(option) + " and " + option_for(name) + " both set " + name + ": give one");
            // The list is the whole set: corners it does not name are unused (0).
            set_values[name] = size_t(i) <= list->size() ? (*list)[size_t(i - 1)] : 0.0;
        }
    }

    // With --region selected the selection is the region; --radius or --s1 then gives the
    // frequency (typed s1, selected region) instead of the selection.
    const auto region = set_values.find(param::region);
    const bool selected_region = region != set_values.end() && region->second == 1;
    const bool radius_given = set_values.count(param::radius) > 0;
    if (radius_given && (set_values.count(param::s1) || set_values.count(param::cutoff)))
        throw UsageError(std::string("--radius and ") + (set_values.count(param::s1) ? "--s1" : "--cutoff") +
                         " both give the feature's frequency: give one");
    if (radius_given && o.selects_region() && !selected_region)
        throw UsageError("--radius and --select-* both give the feature: use one of them (or --region selected to"
                         " filter only the selection at the --radius frequency)");
    if (measure && !o.selects_region())
        throw UsageError("measure needs the feature: --select-sphere, --select-box or --select-stored");

    const size_t wanted = measure ? 1 : 2;
    if (positional.size() < 1 + wanted)
        throw UsageError(std::string("missing ") + (positional.size() < 2 ? "INPUT and OUTPUT" : "OUTPUT") +
                         ": geofilter " + spec.cli_name + " [options] INPUT " + (measure ? "[ELLIPSOID_OUTPUT]" : "OUTPUT"));
    if (positional.size() > 3)
        throw UsageError("too many arguments: '" + positional.back() + "' (options start with --)");
    o.input = positional[1];
    if (positional.size() > 2) o.output = positional[2];

    o.values = default_values(spec, o.selects_region());
    for (const auto& [name, value] : set_values) o.values[name] = value;
    if (selected_region && (radius_given || set_values.count(param::s1) || set_values.count(param::cutoff)))
        o.values[param::use_selection] = 0;
    return o;
}

std::string help_text(const FilterSpec* preset) {
    std::ostringstream os;
    if (!preset) {
        os << "usage: geofilter PRESET [options] INPUT OUTPUT\n"
              "       geofilter measure --select-... INPUT [ELLIPSOID_OUTPUT]\n"
              "       geofilter PRESET --help\n\n";
        os << wrap("Filters a triangle mesh by the frequency of its features (GeoFilter, Kim & Rossignac 2005):"
                   " each eigenmode of the Laplace-Beltrami operator, of frequency s, is scaled by a gain G(s)."
                   " A sphere-like feature of radius r has s = 2/r^2, a cylinder-like one s = 1/r^2. Meshes are"
                   " read and written as " + std::string("PLY, OBJ, OFF or STL") + " (by extension). A point cloud (PLY,"
                   " OBJ or XYZ with vertices and no faces) is filtered through its own Laplacian and written"
                   " with its estimated normals; --select-sphere and --select-box select its points.",
                   0);
        os << "\npresets:\n";
        for (const auto& f : filter_table())
            os << wrap(first_sentence(plain_text(f.description)), 14, "  " + f.cli_name + " ");
        os << "\nfilter options (defaults per preset: geofilter PRESET --help):\n"
              "  --s1 S --s2 S --G0 G --G1 G --Ginf G   the five numbers of eq. 15 (second-order presets)\n"
              "  --zeros A,B,.. --poles C,D,.. --G0 G   polezero: up to 4 zeros and 4 poles (or --z1..--p4)\n"
              "  --solver factored|pcg  --tolerance T  --max-iterations N\n"
              "\nthe feature's size (every filter but denoise):\n"
              "  --radius R                 the feature radius in mesh units [a few % of the diagonal]:\n"
              "                             s = 2/R^2 (--feature-shape sphere) or 1/R^2 (cylinder)\n"
              "  --select-sphere CX,CY,CZ,R the faces whose three vertices lie in this ball\n"
              "  --select-box X0,Y0,Z0,X1,Y1,Z1  ... in this box (both repeatable: the union is taken)\n"
              "  --select-stored            the face selection stored in a PLY input (MeshLab: save with\n"
              "                             face Flags); the selection is measured by an ellipsoid\n"
              "\nwhere to filter:\n"
              "  --region whole|selected|quality  the whole mesh [whole]; only the --select-* faces, fading\n"
              "                             to untouched across --blend-width; or the PLY input's vertex\n"
              "                             quality as a weight in [0, 1]. With --region selected, --radius\n"
              "                             or --s1 gives the frequency and the selection only the region\n"
              "  --blend-width W            the fade band's width in mesh units [0 = the feature radius]\n"
              "\nother options:\n"
              "  --plot FILE.png            draw G(s) on log-log axes (needs gnuplot)\n"
              "  --overwrite-input          allow OUTPUT to be INPUT (refused otherwise)\n"
              "  -q, --quiet                no log, no progress, no summary; only errors\n"
              "  -h, --help                 this text; with a preset: its parameters\n"
              "\nexamples:\n"
              "  geofilter lowpass scan.ply smooth.ply\n"
              "  geofilter exaggerate --radius 0.05 --G1 3 dino.off bumpy.off --plot gain.png\n"
              "  geofilter notch --select-sphere 0.1,0.2,0.3,0.05 in.ply out.ply\n"
              "  geofilter custom --s1 10 --s2 25 --G0 1 --G1 30 --Ginf 0 sphere.off big.off\n"
              "  geofilter polezero --zeros 100,400 --poles 50,800 in.obj out.obj\n"
              "  geofilter measure --select-stored selected.ply\n"              "  geofilter exaggerate --region selected --select-sphere 0,0,1,0.3 in.ply nose.ply\n"
              "\nexit status: 0 done, 1 refused or failed (nothing written), 2 bad command line.\n";
        return os.str();
    }
    const bool measure = preset->kind == FilterKind::Measure;
    os << "usage: geofilter " << preset->cli_name
       << (measure ? " --select-... INPUT [ELLIPSOID_OUTPUT]\n\n" : " [options] INPUT OUTPUT\n\n");
    os << wrap(plain_text(preset->description), 0);
    // The table's texts speak of MeshLab's selection and layers: say what they mean here.
    if (measure)
        os << "\n" << wrap("Here the selection is given by --select-sphere, --select-box or --select-stored; the feature is"
                          " printed, and the ellipsoid written to ELLIPSOID_OUTPUT if given.", 0);
    else
        os << "\n" << wrap("Here useSelection is on when --select-sphere, --select-box or --select-stored is given;"
                          " Otherwise --radius sets the feature's size, unless the frequencies are typed.", 0);
    if (!preset->parameters.empty()) os << "\noptions (default in brackets):\n";
    for (const auto& p : preset->parameters) {
        if (!has_own_option(p)) continue;
        std::string values;
        if (p.type == ParameterType::Enum)
            for (const auto& k : choice_keywords(p)) values += (values.empty() ? " " : "|") + k;
        else if (p.type != ParameterType::Bool)
            values = " " + std::string(p.type == ParameterType::Int ? "N" : "X");
        const std::string negation = p.type == ParameterType::Bool ? ", --no-" + option_for(p.name).substr(2) : "";
        os << "  " << option_for(p.name) << values << negation << "  [" << default_text(p) << "]\n";
        os << wrap(plain_text(p.help), 6);
    }
    if (preset->parameter(param::zero_prefix + "1"))
        os << "  --zeros A,B,..  --poles C,D,..\n"
           << wrap("All zeros (or poles) at once, up to " + std::to_string(param::max_pole_zero) +
                       "; those not listed are unused.",
                   6);
    os << "\nsee geofilter --help for the feature, plot and file options.\n";
    return os.str();
}

} // namespace geofilter::cli
