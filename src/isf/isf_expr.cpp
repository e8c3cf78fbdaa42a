// PASSES WIDTH/HEIGHT expressions: a small recursive-descent evaluator. Written here rather than
// muparser so the headless binary (static libstdc++, carried to the GPU machine) needs no extra
// shared library, and so a bad expression is a value, never an exception.
#include <cctype>
#include <cmath>
#include <cstdlib>

#include "isf/isf.h"

namespace sdfvj {

namespace {

struct ExprParser {
    const std::string& s;
    const std::map<std::string, double>& vars;
    size_t i = 0;
    int depth = 0;
    std::string error;

    void Skip() {
        while (i < s.size() && std::isspace((unsigned char)s[i])) ++i;
    }
    bool Fail(const std::string& msg) {
        if (error.empty()) error = msg + " at character " + std::to_string(i + 1);
        return false;
    }
    bool Accept(char c) {
        Skip();
        if (i < s.size() && s[i] == c) { ++i; return true; }
        return false;
    }
    std::string Name() {
        size_t b = i;
        while (i < s.size() && (std::isalnum((unsigned char)s[i]) || s[i] == '_')) ++i;
        return s.substr(b, i - b);
    }

    // expr := term (('+'|'-') term)*
    bool Expr(double* out) {
        double v = 0;
        if (!Term(&v)) return false;
        for (;;) {
            double r = 0;
            if (Accept('+')) { if (!Term(&r)) return false; v += r; }
            else if (Accept('-')) { if (!Term(&r)) return false; v -= r; }
            else break;
        }
        *out = v;
        return true;
    }
    // term := unary (('*'|'/'|'%') unary)*
    bool Term(double* out) {
        double v = 0;
        if (!Unary(&v)) return false;
        for (;;) {
            double r = 0;
            if (Accept('*')) { if (!Unary(&r)) return false; v *= r; }
            else if (Accept('/')) { if (!Unary(&r)) return false; v /= r; }
            else if (Accept('%')) { if (!Unary(&r)) return false; v = std::fmod(v, r); }
            else break;
        }
        *out = v;
        return true;
    }
    // power := primary ('^' unary)?   (right associative; -2^2 is -(2^2), 2^-1 is 0.5)
    bool Power(double* out) {
        double v = 0;
        if (!Primary(&v)) return false;
        if (Accept('^')) {
            double r = 0;
            if (!Unary(&r)) return false;
            v = std::pow(v, r);
        }
        *out = v;
        return true;
    }
    // unary := ('-'|'+') unary | power
    bool Unary(double* out) {
        if (depth > 200) return Fail("the expression nests too deep");   // recursion depth, not length
        ++depth;
        bool ok;
        if (Accept('-')) { ok = Unary(out); *out = -*out; }
        else if (Accept('+')) ok = Unary(out);
        else ok = Power(out);
        --depth;
        return ok;
    }
    bool Primary(double* out) {
        Skip();
        if (i >= s.size()) return Fail("the expression ends early, expected a number, $VARIABLE or (");
        if (Accept('(')) {
            if (!Expr(out)) return false;
            if (!Accept(')')) return Fail("missing ')'");
            return true;
        }
        if (s[i] == '$') {
            const size_t at = i++;
            std::string n = Name();
            auto it = vars.find(n);
            if (it == vars.end()) {
                i = at;   // the message points at the '$'
                return Fail("unknown variable '$" + n + "', expected $WIDTH, $HEIGHT or an input's name");
            }
            *out = it->second;
            return true;
        }
        if (std::isdigit((unsigned char)s[i]) || s[i] == '.') {
            const char* b = s.c_str() + i;
            char* e = nullptr;
            *out = std::strtod(b, &e);
            if (e == b) return Fail("bad number");
            i += size_t(e - b);
            return true;
        }
        if (std::isalpha((unsigned char)s[i])) {
            std::string n = Name();
            if (n == "pi" || n == "PI") { *out = M_PI; return true; }
            if (n == "e" || n == "E") { *out = M_E; return true; }
            if (!Accept('(')) return Fail("unknown name '" + n + "', expected a function call such as floor(...) or $VARIABLE");
            double args[2] = {0, 0};
            int argc = 0;
            if (!Accept(')')) {
                do {
                    if (argc == 2) return Fail("too many arguments to " + n);
                    if (!Expr(&args[argc++])) return false;
                } while (Accept(','));
                if (!Accept(')')) return Fail("missing ')' after the arguments of " + n);
            }
            struct Fn1 { const char* name; double (*f)(double); };
            static const Fn1 kOne[] = {{"floor", std::floor}, {"ceil", std::ceil}, {"round", std::round},
                                       {"abs", std::fabs},    {"sqrt", std::sqrt}, {"exp", std::exp},
                                       {"log", std::log},     {"sin", std::sin},   {"cos", std::cos},
                                       {"tan", std::tan},     {"trunc", std::trunc}};
            for (const Fn1& f : kOne)
                if (n == f.name) {
                    if (argc != 1) return Fail(n + " takes 1 argument");
                    *out = f.f(args[0]);
                    return true;
                }
            if (n == "min" || n == "max" || n == "pow") {
                if (argc != 2) return Fail(n + " takes 2 arguments");
                *out = n == "min" ? std::fmin(args[0], args[1]) : n == "max" ? std::fmax(args[0], args[1]) : std::pow(args[0], args[1]);
                return true;
            }
            return Fail("unknown function '" + n + "', expected floor ceil round trunc abs sqrt exp log sin cos tan min max pow");
        }
        return Fail(std::string("unexpected '") + s[i] + "'");
    }
};

}  // namespace

bool EvalIsfExpression(const std::string& expr, const std::map<std::string, double>& vars, double* out, std::string* error) {
    if (expr.size() > 1024) {
        *error = "the expression is longer than 1024 characters, expected a short formula";
        return false;
    }
    ExprParser p{expr, vars};
    double v = 0;
    if (!p.Expr(&v)) {
        *error = p.error;
        return false;
    }
    p.Skip();
    if (p.i != expr.size()) {
        p.Fail(std::string("unexpected '") + expr[p.i] + "'");
        *error = p.error + ", expected the end of the expression";
        return false;
    }
    if (!std::isfinite(v)) {
        *error = "the expression is not a finite number (division by zero?)";
        return false;
    }
    *out = v;
    return true;
}

}  // namespace sdfvj
