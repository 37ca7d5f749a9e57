#include <cstdio>
int main() { std::puts("vtm"); return 0; }
