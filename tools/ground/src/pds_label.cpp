#include "vtm/ground/pds_label.hpp"

#include <cmath>

#include "vtm/core/text_number.hpp"

namespace vtm::ground {
namespace {

bool isBlank(unsigned char c) { return c == ' ' || c == '\t'; }
bool isLineEnd(unsigned char c) { return c == '\r' || c == '\n'; }
bool isText(unsigned char c) { return (c >= 0x20U && c <= 0x7EU) || c == '\t' || isLineEnd(c); }

std::string trim(const std::string& s) {
    std::size_t a = 0;
    std::size_t b = s.size();
    while (a < b && isBlank(static_cast<unsigned char>(s[a]))) ++a;
    while (b > a && isBlank(static_cast<unsigned char>(s[b - 1U]))) --b;
    return s.substr(a, b - a);
}

// One pass over the label bytes; every loop advances pos_ or ends, so the work is linear
// in the label's size (at most kMaxPdsLabelBytes).
class LabelParser {
public:
    LabelParser(const std::vector<unsigned char>& bytes, const std::string& name)
        : b_(bytes), n_(bytes.size() < kMaxPdsLabelBytes ? bytes.size() : kMaxPdsLabelBytes), name_(name) {}
    Result<PdsLabel> run();

private:
    std::string error(const std::string& what) const {
        return name_ + ": PDS label line " + std::to_string(line_) + ": " + what;
    }
    std::string notText(const std::string& context) const {
        return "byte " + std::to_string(pos_) + " (" + std::to_string(b_[pos_]) + ") is not text (" + context + ")";
    }
    std::string skipSpace(bool cross_lines);
    std::string skipComment();
    std::string readKey(std::string& key);
    std::string readValue(std::string& value);
    std::string readQuoted(std::string& out);
    std::string readList(std::string& out);
    std::string readBare(std::string& out);
    std::string restOfLineBlank();
    std::string statement(const std::string& key, const std::string& value, std::size_t key_line);

    const std::vector<unsigned char>& b_;
    std::size_t n_;
    const std::string& name_;
    std::size_t pos_ = 0;
    std::size_t line_ = 1;
    std::vector<std::string> scopes_;
    PdsLabel label_;
};

// Advances over blanks and comments (and line ends when cross_lines); checks each byte is text.
std::string LabelParser::skipSpace(bool cross_lines) {
    while (pos_ < n_) {
        const unsigned char c = b_[pos_];
        if (!isText(c)) return error(notText("no END line before it"));
        if (c == '/' && pos_ + 1U < n_ && b_[pos_ + 1U] == '*') {
            const std::string e = skipComment();
            if (!e.empty()) return e;
            continue;
        }
        if (isBlank(c) || (cross_lines && isLineEnd(c))) {
            if (c == '\n') ++line_;
            ++pos_;
            continue;
        }
        break;
    }
    return "";
}

std::string LabelParser::skipComment() {
    for (std::size_t i = pos_ + 2U; i + 1U < n_ && !isLineEnd(b_[i]); ++i) {
        if (b_[i] == '*' && b_[i + 1U] == '/') {
            pos_ = i + 2U;
            return "";
        }
    }
    return error("comment '/*' not closed on its line");
}

std::string LabelParser::readKey(std::string& key) {
    const std::size_t start = pos_;
    while (pos_ < n_) {
        const unsigned char c = b_[pos_];
        if (c == '=' || isBlank(c) || isLineEnd(c) || !isText(c)) break;
        ++pos_;
    }
    key.assign(b_.begin() + static_cast<std::ptrdiff_t>(start), b_.begin() + static_cast<std::ptrdiff_t>(pos_));
    return "";
}

std::string LabelParser::readQuoted(std::string& out) {
    const std::size_t start_line = line_;
    out = "\"";
    for (++pos_; pos_ < n_; ++pos_) {
        const unsigned char c = b_[pos_];
        if (!isText(c)) {
            line_ = start_line;
            return error(notText("string not closed before it"));
        }
        if (c == '"') {
            ++pos_;
            out += '"';
            return "";
        }
        if (c == '\n') ++line_;
        if (isLineEnd(c)) continue;  // a string over several lines: its lines joined
        out += static_cast<char>(c);
    }
    line_ = start_line;
    return error("string not closed (no '\"' before the end of the label)");
}

// A list "( ... )" or set "{ ... }", nested; blanks and line ends outside strings dropped.
std::string LabelParser::readList(std::string& out) {
    const std::size_t start_line = line_;
    std::size_t depth = 0;
    while (pos_ < n_) {
        const unsigned char c = b_[pos_];
        if (!isText(c)) {
            line_ = start_line;
            return error(notText("list not closed before it"));
        }
        if (c == '"') {
            std::string s;
            const std::string e = readQuoted(s);
            if (!e.empty()) return e;
            out += s;
            continue;
        }
        ++pos_;
        if (c == '\n') ++line_;
        if (isBlank(c) || isLineEnd(c)) continue;
        out += static_cast<char>(c);
        if (c == '(' || c == '{') {
            if (++depth > kMaxPdsNesting) return error("list nested more than " + std::to_string(kMaxPdsNesting) + " deep");
        } else if (c == ')' || c == '}') {
            if (--depth == 0U) return "";
        }
    }
    line_ = start_line;
    return error("list not closed (no ')' before the end of the label)");
}

// A value on the rest of the line, up to a comment, blanks at its ends dropped.
std::string LabelParser::readBare(std::string& out) {
    const std::size_t start = pos_;
    while (pos_ < n_ && !isLineEnd(b_[pos_])) {
        if (!isText(b_[pos_])) return error(notText("no END line before it"));
        if (b_[pos_] == '/' && pos_ + 1U < n_ && b_[pos_ + 1U] == '*') break;
        ++pos_;
    }
    out = trim(std::string(b_.begin() + static_cast<std::ptrdiff_t>(start), b_.begin() + static_cast<std::ptrdiff_t>(pos_)));
    return "";
}

// After a value: only blanks or a comment up to the line's end.
std::string LabelParser::restOfLineBlank() {
    const std::string e = skipSpace(false);
    if (!e.empty()) return e;
    if (pos_ < n_ && !isLineEnd(b_[pos_])) return error("unexpected text after the value");
    return "";
}

// The value after '=' (on the same line, or on the next one when the line ends there).
std::string LabelParser::readValue(std::string& value) {
    std::string e = skipSpace(true);
    if (!e.empty()) return e;
    if (pos_ >= n_) return error("value missing at the end of the label");
    const unsigned char c = b_[pos_];
    if (c == '"') {
        e = readQuoted(value);
    } else if (c == '(' || c == '{') {
        e = readList(value);
    } else {
        e = readBare(value);
    }
    if (!e.empty()) return e;
    if (value.empty()) return error("empty value");
    if (c == '"' || c == '(' || c == '{') {
        // A unit may follow a list or string ("(1,2) <m>"): kept with the value.
        e = skipSpace(false);
        if (!e.empty()) return e;
        if (pos_ < n_ && b_[pos_] == '<') {
            std::string unit;
            e = readBare(unit);
            if (!e.empty()) return e;
            value += " " + unit;
        }
    }
    return restOfLineBlank();
}

std::string LabelParser::statement(const std::string& key, const std::string& value, std::size_t key_line) {
    const bool opens = key == "GROUP" || key == "OBJECT" || key == "BEGIN_GROUP" || key == "BEGIN_OBJECT";
    const bool closes = key == "END_GROUP" || key == "END_OBJECT";
    if (opens) {
        if (scopes_.size() >= kMaxPdsNesting) return error(key + " nested more than " + std::to_string(kMaxPdsNesting) + " deep");
        scopes_.push_back(pdsText(value));
        return "";
    }
    if (closes) {
        if (scopes_.empty()) return error(key + " without an open GROUP/OBJECT");
        if (!value.empty() && pdsText(value) != scopes_.back()) {
            return error(key + " = " + value + " closes " + scopes_.back());
        }
        scopes_.pop_back();
        return "";
    }
    if (label_.statements.size() >= kMaxPdsStatements) {
        return error("more than " + std::to_string(kMaxPdsStatements) + " statements");
    }
    std::string scope;
    for (const std::string& s : scopes_) scope += (scope.empty() ? "" : "/") + s;
    label_.statements.push_back(PdsStatement{scope, key, value, key_line});
    return "";
}

Result<PdsLabel> LabelParser::run() {
    for (;;) {
        std::string e = skipSpace(true);
        if (!e.empty()) return Result<PdsLabel>::failure(e);
        if (pos_ >= n_) {
            const std::string where = n_ == kMaxPdsLabelBytes ? "in the first " + std::to_string(n_) + " bytes" : "";
            return Result<PdsLabel>::failure(name_ + ": PDS label has no END line" + (where.empty() ? "" : " " + where));
        }
        const std::size_t key_line = line_;
        std::string key;
        (void)readKey(key);
        if (key.empty()) return Result<PdsLabel>::failure(error("statement without a key"));
        if (key == "END") {
            e = restOfLineBlank();
            if (!e.empty()) return Result<PdsLabel>::failure(e);
            if (!scopes_.empty()) return Result<PdsLabel>::failure(error("END inside GROUP/OBJECT " + scopes_.back()));
            while (pos_ < n_ && isLineEnd(b_[pos_]) && b_[pos_] != '\n') ++pos_;
            if (pos_ < n_) ++pos_;  // the '\n'
            label_.end_offset = pos_;
            break;
        }
        e = skipSpace(false);
        if (!e.empty()) return Result<PdsLabel>::failure(e);
        std::string value;
        if (pos_ < n_ && b_[pos_] == '=') {
            ++pos_;
            e = readValue(value);
        } else if (key != "END_GROUP" && key != "END_OBJECT") {
            e = error("no '=' after " + key);
        }
        if (e.empty()) e = statement(key, value, key_line);
        if (!e.empty()) return Result<PdsLabel>::failure(e);
        if (label_.statements.size() == 1U && (key != "PDS_VERSION_ID" || pdsText(value) != "PDS3")) {
            return Result<PdsLabel>::failure(name_ + ": not a PDS3 label (the first statement must be PDS_VERSION_ID = PDS3)");
        }
    }
    if (label_.statements.empty()) {
        return Result<PdsLabel>::failure(name_ + ": not a PDS3 label (END before PDS_VERSION_ID = PDS3)");
    }
    return Result<PdsLabel>::success(std::move(label_));
}

// "1.5 <rad>" -> "1.5"; false when a '<' has no closing '>' at the end.
bool stripUnit(const std::string& value, std::string& number) {
    const std::size_t lt = value.find('<');
    if (lt == std::string::npos) {
        number = trim(value);
        return true;
    }
    if (value.back() != '>' || value.find('>') != value.size() - 1U) return false;
    number = trim(value.substr(0, lt));
    return true;
}

// A finite decimal number: digits, sign, '.', exponent only (no hex, nan, inf, blanks).
bool realField(const std::string& text, double& out) {
    if (text.empty() || text.size() > 64U) return false;
    for (const char c : text) {
        const bool ok = (c >= '0' && c <= '9') || c == '+' || c == '-' || c == '.' || c == 'e' || c == 'E';
        if (!ok) return false;
    }
    double v = 0.0;
    if (!text::parseReal(text.c_str(), v) || !std::isfinite(v)) return false;
    out = v;
    return true;
}

}  // namespace

const PdsStatement* PdsLabel::find(const std::string& scope, const std::string& key) const {
    for (const PdsStatement& s : statements) {
        if (s.scope == scope && s.key == key) return &s;
    }
    return nullptr;
}

std::vector<std::string> PdsLabel::scopesWhere(const std::string& key, const std::string& value) const {
    std::vector<std::string> scopes;
    for (const PdsStatement& s : statements) {
        if (s.key != key || pdsText(s.value) != value) continue;
        bool seen = false;
        for (const std::string& t : scopes) seen = seen || t == s.scope;
        if (!seen) scopes.push_back(s.scope);
    }
    return scopes;
}

Result<PdsLabel> parsePdsLabel(const std::vector<unsigned char>& bytes, const std::string& name) {
    return LabelParser(bytes, name).run();
}

bool pdsReal(const std::string& value, double& out) {
    std::string number;
    return stripUnit(value, number) && realField(number, out);
}

bool pdsReals(const std::string& value, std::size_t n, std::vector<double>& out) {
    std::string body;
    if (!stripUnit(value, body) || body.size() < 2U || body.front() != '(' || body.back() != ')') return false;
    std::vector<double> values;
    std::size_t start = 1;
    while (start < body.size()) {
        std::size_t comma = body.find(',', start);
        if (comma == std::string::npos) comma = body.size() - 1U;
        double v = 0.0;
        if (values.size() >= n || !pdsReal(body.substr(start, comma - start), v)) return false;
        values.push_back(v);
        start = comma + 1U;
    }
    if (values.size() != n) return false;
    out = values;
    return true;
}

bool pdsUnsigned(const std::string& value, std::uint64_t max_value, std::uint64_t& out) {
    std::string number;
    return stripUnit(value, number) && text::parseUnsigned(number.c_str(), max_value, out);
}

std::string pdsText(const std::string& value) {
    if (value.size() >= 2U && value.front() == '"' && value.back() == '"') return value.substr(1, value.size() - 2U);
    return value;
}

}  // namespace vtm::ground
