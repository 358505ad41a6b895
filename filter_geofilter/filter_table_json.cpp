// Prints the filter table (filter_table.cpp) as JSON. The build writes it to
// filter_table.json, from which the Python test harnesses and experiments take filter names,
// parameters and defaults instead of repeating them.
#include "filter_table.h"

#include <cstdio>
#include <iostream>
#include <string>

namespace {

std::string quoted(const std::string& s) {
    std::string out = "\"";
    for (const char c : s) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char escape[8];
            std::snprintf(escape, sizeof escape, "\\u%04x", c);
            out += escape;
        } else {
            out += c;
        }
    }
    return out + "\"";
}

// Round-trips: a default read back in Python is the double the table holds.
std::string number(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.17g", v);
    return buffer;
}

const char* type_name(geofilter::ParameterType t) {
    switch (t) {
    case geofilter::ParameterType::Float: return "Float";
    case geofilter::ParameterType::Bool: return "Bool";
    case geofilter::ParameterType::Int: return "Int";
    case geofilter::ParameterType::Enum: return "Enum";
    case geofilter::ParameterType::Length: return "Length";
    }
    return "?";
}

const char* kind_name(geofilter::FilterKind k) {
    switch (k) {
    case geofilter::FilterKind::SecondOrder: return "SecondOrder";
    case geofilter::FilterKind::PoleZero: return "PoleZero";
    case geofilter::FilterKind::Measure: return "Measure";
    case geofilter::FilterKind::Butterworth: return "Butterworth";
    case geofilter::FilterKind::Denoise: return "Denoise";
    }
    return "?";
}

} // namespace

int main() {
    std::string out = "[\n";
    const auto& table = geofilter::filter_table();
    for (size_t f = 0; f < table.size(); ++f) {
        const auto& spec = table[f];
        out += "  {\"name\": " + quoted(spec.name) + ", \"python_name\": " + quoted(spec.python_name) +
               ", \"cli_name\": " + quoted(spec.cli_name) + ", \"kind\": " + quoted(kind_name(spec.kind));
        if (spec.kind == geofilter::FilterKind::SecondOrder) {
            const auto& r = spec.reference;  // the paper's design the preset is named after
            out += ", \"reference\": {\"s1\": " + number(r.s1) + ", \"s2\": " + number(r.s2) + ", \"G0\": " + number(r.G0) +
                   ", \"G1\": " + number(r.G1) + ", \"Ginf\": " + number(r.Ginf) + "}";
        }
        out += ", \"parameters\": [";
        for (size_t p = 0; p < spec.parameters.size(); ++p) {
            const auto& param = spec.parameters[p];
            out += std::string(p ? "," : "") + "\n    {\"name\": " + quoted(param.name) + ", \"type\": " +
                   quoted(type_name(param.type)) + ", \"default\": " + number(param.default_value) + ", \"choices\": [";
            for (size_t c = 0; c < param.choices.size(); ++c) out += (c ? ", " : "") + quoted(param.choices[c]);
            out += "]}";
        }
        out += std::string(spec.parameters.empty() ? "" : "\n  ") + "]}" + (f + 1 < table.size() ? "," : "") + "\n";
    }
    std::cout << out << "]\n";
    return std::cout ? 0 : 1;
}
