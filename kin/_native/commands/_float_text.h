/*
 * The shortest decimal text of a float64 that reads back as the same float64, for the JSON
 * lines _plain_lines.c writes (about 20 times faster than float.__repr__ here).
 *
 * Grisu2 (F. Loitsch, "Printing floating-point numbers quickly and accurately with integers",
 * PLDI 2010): the value and the two bounds of its rounding interval scaled by a cached power of
 * ten into 64-bit integers, then the digits generated until the number lies inside the interval.
 * What it writes always reads back as the same float64 and has at most 17 digits; in nearly
 * every case (all but about one value in a thousand, tests/native/test_plain_lines.py counts them) it
 * is the text Python's repr writes: the shortest, and of the shortest the nearest the value.
 * Else a digit or two longer, or another of the shortest. Laid out as repr lays
 * it out: "0.001", "123.0", "1e-05", "1.5e+16", "-0.0"; NaN and the infinities as the json
 * module writes them ("NaN", "Infinity", "-Infinity").
 */
#ifndef KIN_COMMANDS_FLOAT_TEXT_H
#define KIN_COMMANDS_FLOAT_TEXT_H

#include <math.h>
#include <stdint.h>
#include <string.h>

/* The longest text float_text writes: "-1.2345678901234567e-308" and a spare. */
#define FLOAT_TEXT_MAX 32

/* A number f * 2^e, f a 64-bit integer. */
typedef struct {
    uint64_t f;
    int e;
} Fp;

/* 10^k for k = -348, -340, ..., 340: the 64-bit f (rounded to nearest, top bit set) and e,
   made with exact integers: e such that 2^63 <= 10^k / 2^e < 2^64, f = round(10^k / 2^e). */
static const Fp cached_powers[87] = {
    {0xfa8fd5a0081c0288u, -1220}, {0xbaaee17fa23ebf76u, -1193}, {0x8b16fb203055ac76u, -1166},
    {0xcf42894a5dce35eau, -1140}, {0x9a6bb0aa55653b2du, -1113}, {0xe61acf033d1a45dfu, -1087},
    {0xab70fe17c79ac6cau, -1060}, {0xff77b1fcbebcdc4fu, -1034}, {0xbe5691ef416bd60cu, -1007},
    {0x8dd01fad907ffc3cu, -980}, {0xd3515c2831559a83u, -954}, {0x9d71ac8fada6c9b5u, -927},
    {0xea9c227723ee8bcbu, -901}, {0xaecc49914078536du, -874}, {0x823c12795db6ce57u, -847},
    {0xc21094364dfb5637u, -821}, {0x9096ea6f3848984fu, -794}, {0xd77485cb25823ac7u, -768},
    {0xa086cfcd97bf97f4u, -741}, {0xef340a98172aace5u, -715}, {0xb23867fb2a35b28eu, -688},
    {0x84c8d4dfd2c63f3bu, -661}, {0xc5dd44271ad3cdbau, -635}, {0x936b9fcebb25c996u, -608},
    {0xdbac6c247d62a584u, -582}, {0xa3ab66580d5fdaf6u, -555}, {0xf3e2f893dec3f126u, -529},
    {0xb5b5ada8aaff80b8u, -502}, {0x87625f056c7c4a8bu, -475}, {0xc9bcff6034c13053u, -449},
    {0x964e858c91ba2655u, -422}, {0xdff9772470297ebdu, -396}, {0xa6dfbd9fb8e5b88fu, -369},
    {0xf8a95fcf88747d94u, -343}, {0xb94470938fa89bcfu, -316}, {0x8a08f0f8bf0f156bu, -289},
    {0xcdb02555653131b6u, -263}, {0x993fe2c6d07b7facu, -236}, {0xe45c10c42a2b3b06u, -210},
    {0xaa242499697392d3u, -183}, {0xfd87b5f28300ca0eu, -157}, {0xbce5086492111aebu, -130},
    {0x8cbccc096f5088ccu, -103}, {0xd1b71758e219652cu, -77}, {0x9c40000000000000u, -50},
    {0xe8d4a51000000000u, -24}, {0xad78ebc5ac620000u, 3}, {0x813f3978f8940984u, 30},
    {0xc097ce7bc90715b3u, 56}, {0x8f7e32ce7bea5c70u, 83}, {0xd5d238a4abe98068u, 109},
    {0x9f4f2726179a2245u, 136}, {0xed63a231d4c4fb27u, 162}, {0xb0de65388cc8ada8u, 189},
    {0x83c7088e1aab65dbu, 216}, {0xc45d1df942711d9au, 242}, {0x924d692ca61be758u, 269},
    {0xda01ee641a708deau, 295}, {0xa26da3999aef774au, 322}, {0xf209787bb47d6b85u, 348},
    {0xb454e4a179dd1877u, 375}, {0x865b86925b9bc5c2u, 402}, {0xc83553c5c8965d3du, 428},
    {0x952ab45cfa97a0b3u, 455}, {0xde469fbd99a05fe3u, 481}, {0xa59bc234db398c25u, 508},
    {0xf6c69a72a3989f5cu, 534}, {0xb7dcbf5354e9beceu, 561}, {0x88fcf317f22241e2u, 588},
    {0xcc20ce9bd35c78a5u, 614}, {0x98165af37b2153dfu, 641}, {0xe2a0b5dc971f303au, 667},
    {0xa8d9d1535ce3b396u, 694}, {0xfb9b7cd9a4a7443cu, 720}, {0xbb764c4ca7a44410u, 747},
    {0x8bab8eefb6409c1au, 774}, {0xd01fef10a657842cu, 800}, {0x9b10a4e5e9913129u, 827},
    {0xe7109bfba19c0c9du, 853}, {0xac2820d9623bf429u, 880}, {0x80444b5e7aa7cf85u, 907},
    {0xbf21e44003acdd2du, 933}, {0x8e679c2f5e44ff8fu, 960}, {0xd433179d9c8cb841u, 986},
    {0x9e19db92b4e31ba9u, 1013}, {0xeb96bf6ebadf77d9u, 1039}, {0xaf87023b9bf0ee6bu, 1066},
};

/* x * y, the product's top 64 bits rounded. */
static inline Fp fp_mul(Fp x, Fp y)
{
    const uint64_t m32 = 0xFFFFFFFFu;
    uint64_t a = x.f >> 32, b = x.f & m32, c = y.f >> 32, d = y.f & m32;
    uint64_t ac = a * c, bc = b * c, ad = a * d, bd = b * d;
    uint64_t mid = (bd >> 32) + (ad & m32) + (bc & m32) + (1u << 31);
    Fp out = {ac + (ad >> 32) + (bc >> 32) + (mid >> 32), x.e + y.e + 64};
    return out;
}

/* v shifted left until its top bit is set. */
static inline Fp fp_normalize(Fp v)
{
    while (!(v.f & ((uint64_t)1 << 63))) {
        v.f <<= 1;
        v.e--;
    }
    return v;
}

/* The cached power c = 10^-k with the product of c and a number of exponent e (a normalized
   bound) of exponent in [-60, -32]; *k set to k. */
static inline Fp cached_power(int e, int *k)
{
    double dk = (-61 - e) * 0.30102999566398114 + 347; /* log10(2) */
    int n = (int)dk;
    if (dk - n > 0.0) n++;
    unsigned index = (unsigned)((n >> 3) + 1);
    *k = -(-348 + (int)(index << 3));
    return cached_powers[index];
}

/* 10^0 .. 10^19. */
static const uint64_t powers_of_ten[20] = {
    1u, 10u, 100u, 1000u,
    10000u, 100000u, 1000000u, 10000000u,
    100000000u, 1000000000u, 10000000000u, 100000000000u,
    1000000000000u, 10000000000000u, 100000000000000u, 1000000000000000u,
    10000000000000000u, 100000000000000000u, 1000000000000000000u, 10000000000000000000u,
};

/* The last digit moved down while the number stays in the interval and gets nearer the value
   (rest: what is left below the digits, ten_kappa: one unit of the last digit, wp_w: the upper
   bound minus the value, all in the same scale). */
static inline void grisu_round(char *digits, int length, uint64_t delta, uint64_t rest,
                               uint64_t ten_kappa, uint64_t wp_w)
{
    while (rest < wp_w && delta - rest >= ten_kappa &&
           (rest + ten_kappa < wp_w || wp_w - rest > rest + ten_kappa - wp_w)) {
        digits[length - 1]--;
        rest += ten_kappa;
    }
}

/* The digits of the number inside (mp - delta, mp] nearest w, with *k the power of ten of the
   last one; their count. */
static inline int digit_gen(Fp w, Fp mp, uint64_t delta, char *digits, int *k)
{
    const Fp one = {(uint64_t)1 << -mp.e, mp.e};
    const uint64_t wp_w = mp.f - w.f;
    uint32_t p1 = (uint32_t)(mp.f >> -one.e);
    uint64_t p2 = mp.f & (one.f - 1);
    int kappa = 1, length = 0;
    while (kappa < 10 && p1 >= powers_of_ten[kappa]) kappa++;
    while (kappa > 0) {
        uint32_t unit = (uint32_t)powers_of_ten[kappa - 1];
        uint32_t d = p1 / unit;
        p1 %= unit;
        if (d || length) digits[length++] = (char)('0' + d);
        kappa--;
        uint64_t rest = ((uint64_t)p1 << -one.e) + p2;
        if (rest <= delta) {
            *k += kappa;
            grisu_round(digits, length, delta, rest, powers_of_ten[kappa] << -one.e, wp_w);
            return length;
        }
    }
    for (;;) { /* kappa <= 0: the fraction's digits */
        p2 *= 10;
        delta *= 10;
        char d = (char)(p2 >> -one.e);
        if (d || length) digits[length++] = (char)('0' + d);
        p2 &= one.f - 1;
        kappa--;
        if (p2 < delta) {
            *k += kappa;
            int index = -kappa;
            grisu_round(digits, length, delta, p2, one.f,
                        index < 20 ? wp_w * powers_of_ten[index] : 0);
            return length;
        }
    }
}

/* The digits of a finite value > 0 (at most 17) and *k: value = digits * 10^k. */
static inline int grisu2(double value, char *digits, int *k)
{
    uint64_t bits;
    memcpy(&bits, &value, sizeof bits);
    const uint64_t hidden = (uint64_t)1 << 52;
    int biased = (int)((bits >> 52) & 0x7FF);
    Fp v = {bits & (hidden - 1), -1074};
    if (biased != 0) {
        v.f |= hidden;
        v.e = biased - 1075;
    }
    /* The bounds of the rounding interval, halfway to the neighbours (nearer below a power
       of two), the upper one normalized and the lower one at its exponent. */
    Fp plus = fp_normalize((Fp){(v.f << 1) + 1, v.e - 1});
    Fp minus = v.f == hidden ? (Fp){(v.f << 2) - 1, v.e - 2} : (Fp){(v.f << 1) - 1, v.e - 1};
    minus.f <<= minus.e - plus.e;
    minus.e = plus.e;
    Fp c = cached_power(plus.e, k);
    Fp w = fp_mul(fp_normalize(v), c);
    Fp wp = fp_mul(plus, c), wm = fp_mul(minus, c);
    wm.f++;
    wp.f--;
    return digit_gen(w, wp, wp.f - wm.f, digits, k);
}

/* Writes the exponent as repr does ("e-05", "e+16", "e-308"). */
static inline char *write_exponent(char *out, int exponent)
{
    *out++ = 'e';
    *out++ = exponent < 0 ? '-' : '+';
    if (exponent < 0) exponent = -exponent;
    if (exponent >= 100) {
        *out++ = (char)('0' + exponent / 100);
        exponent %= 100;
    }
    *out++ = (char)('0' + exponent / 10);
    *out++ = (char)('0' + exponent % 10);
    return out;
}

/* The text of value at out (no terminating zero; at most FLOAT_TEXT_MAX characters); returns
   the end of the text. */
static inline char *float_text(double value, char *out)
{
    if (value != value) {
        memcpy(out, "NaN", 3);
        return out + 3;
    }
    if (signbit(value)) {
        *out++ = '-';
        value = -value;
    }
    if (value == 0.0) {
        memcpy(out, "0.0", 3);
        return out + 3;
    }
    if (isinf(value)) {
        memcpy(out, "Infinity", 8);
        return out + 8;
    }
    char digits[20];
    int k = 0;
    int length = grisu2(value, digits, &k);
    int point = length + k; /* value = 0.digits * 10^point */
    if (point <= -4 || point > 16) { /* d.ddde+XX */
        *out++ = digits[0];
        if (length > 1) {
            *out++ = '.';
            memcpy(out, digits + 1, (size_t)(length - 1));
            out += length - 1;
        }
        return write_exponent(out, point - 1);
    }
    if (point <= 0) { /* 0.000ddd */
        *out++ = '0';
        *out++ = '.';
        memset(out, '0', (size_t)-point);
        out += -point;
        memcpy(out, digits, (size_t)length);
        return out + length;
    }
    if (point >= length) { /* ddd000.0 */
        memcpy(out, digits, (size_t)length);
        out += length;
        memset(out, '0', (size_t)(point - length));
        out += point - length;
        memcpy(out, ".0", 2);
        return out + 2;
    }
    memcpy(out, digits, (size_t)point); /* ddd.ddd */
    out += point;
    *out++ = '.';
    memcpy(out, digits + point, (size_t)(length - point));
    return out + length - point;
}

#endif
