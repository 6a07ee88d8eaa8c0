// Internals of vision::Segmenter's stage 2 shared with its tests: the row conversion of RGB
// pixels to Y, U and V planes in its two forms. Not part of the public API: include segment.h.
#pragma once

#include <cstdint>

namespace patlab::vision::internal {

// image.h's BT.601 RgbToYuv of the n pixels of a packed RGB row into three planes, exactly: the
// portable element-wise loop (vectorised by the compiler).
void RgbRowToYuv(const uint8_t* in, int n, uint8_t* c0, uint8_t* c1, uint8_t* c2);

// The same conversion in place on the n pixels' R, G and B planes (c0, c1, c2 become Y, U, V):
// the second pass of RgbRowToYuv, for rows read with any strides.
void RgbPlanesToYuv(int n, uint8_t* c0, uint8_t* c1, uint8_t* c2);

// Whether this build has the AVX-512 (BW + VBMI) forms of stage 2: the row conversion below and
// the classification by byte tables (segment.h). Fixed at compile time (-march).
bool HaveAvx512Rows();

// The same conversion 32 pixels at a time with byte multiply-adds; the same bytes as RgbRowToYuv.
// Without HaveAvx512Rows(), RgbRowToYuv itself.
void RgbRowToYuvAvx512(const uint8_t* in, int n, uint8_t* c0, uint8_t* c1, uint8_t* c2);

}  // namespace patlab::vision::internal
