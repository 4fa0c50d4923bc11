/* Wine 8 (Debian 12's) lacks bcryptprimitives.dll, which Windows has had since Windows 8 and which
 * the Rust standard library (1.78 and later) imports for ProcessPrng. This stand-in, placed beside
 * the test program, lets the FMU's DLL load under that Wine; on Windows the system's own is used.
 * It is for the tests only and is not packaged. */
#include <windows.h>

BOOLEAN WINAPI SystemFunction036(PVOID buffer, ULONG length); /* RtlGenRandom, advapi32 */

__declspec(dllexport) BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T length) {
    while (length > 0) {
        ULONG chunk = length > 0x10000000 ? 0x10000000 : (ULONG)length;
        if (!SystemFunction036(data, chunk)) return FALSE;
        data += chunk;
        length -= chunk;
    }
    return TRUE;
}
