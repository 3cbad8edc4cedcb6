#include <cstdio>
int main() { std::puts("tear"); return 0; }
