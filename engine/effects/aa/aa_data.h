// Anti-aliasing's texture units, shared by aa.cpp and resolve.frag (it has no uniform block).
#ifndef CANDELA_AA_DATA_H
#define CANDELA_AA_DATA_H
#define AA_HDR_UNIT 0    // the multisampled (or sub-frame) radiance
#define AA_DEPTH_UNIT 1  // its depth
#endif
