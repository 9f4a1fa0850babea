#include <cstdio>
int main() { std::puts("shvol " SHVOL_VERSION); return 0; }
