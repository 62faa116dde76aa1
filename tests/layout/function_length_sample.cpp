// SPDX-License-Identifier: MIT
// A sample for check_function_length_selftest.sh, not built: braces in comments,
// strings, characters, raw strings and preprocessor lines, K&R and Allman braces,
// multi-line signatures, C++ members.  Only at_limit_plus_one is over 100 lines.
#define OPEN {
#define CLOSE(x) x }
/* } } } */
extern "C" {
static const char *brace = "}}{";
static const int table[] = { 1, 2, 3 };

static int at_limit(int a,
		    int b)
{
	char c = '}';
#if defined(SOMETHING)
	if (a) {
#else
	if (b) {
#endif
		c++;
	}
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	a += b; /* } */
	return a + c;
}

int at_limit_plus_one(int a, const char *s) {
	const char *r = R"x(}})x";
	// }
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	a += s[0] == '{';
	return a + (r[0] == '}');
}
}

namespace sample {
class Node : public Base {
public:
	Node() : a_{1}, b_(2) { start(); }
	auto size() const -> int { return a_; }
	bool operator()(int x) const noexcept { return x == b_; }
private:
	int a_, b_;
};
enum class Kind { a = 1, b = (2) };
} // namespace sample
