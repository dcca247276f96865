/*
 * RayMappersExpatFix: lets ParaView 5.11's VTK (9.2) parse XML data again under Debian 12's
 * libexpat (2.5.0-1+deb12u*), which carries the backported fix of CVE-2023-52425
 * ("reparse deferral", expat 2.6). VTK 9.2's vtkXMLParser feeds the parser in chunks and
 * stops at the raw appended data; with deferral on, the parser has not yet reported the
 * elements before that point, so every in-memory XML data set fails to parse
 * ("not well-formed (invalid token)", VTK issue 19258, fixed in later VTK by turning
 * deferral off). ParaView moves data between MPI ranks through such XML (DIY
 * serialization: RedistributeDataSet, the ordered-compositing redistribution of volumes),
 * so under mpirun nothing would arrive.
 *
 * Preloaded (LD_PRELOAD, see raymappers-env), this library wraps the parser constructors
 * and reset and turns deferral off on every parser, the behaviour of expat <= 2.5.
 * Nothing else changes. Without XML_SetReparseDeferralEnabled (an unpatched expat) it
 * only forwards.
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <expat.h>

typedef XML_Parser (*CreateFn)(const XML_Char*);
typedef XML_Parser (*CreateNSFn)(const XML_Char*, XML_Char);
typedef XML_Parser (*CreateMMFn)(const XML_Char*, const XML_Memory_Handling_Suite*,
  const XML_Char*);
typedef XML_Bool (*ResetFn)(XML_Parser, const XML_Char*);
typedef XML_Bool (*SetDeferralFn)(XML_Parser, XML_Bool);

static void* next_symbol(const char* name)
{
  return dlsym(RTLD_NEXT, name);
}

static XML_Parser without_deferral(XML_Parser parser)
{
  static SetDeferralFn set_deferral = 0;
  static int looked_up = 0;
  if (!looked_up)
  {
    set_deferral = (SetDeferralFn)next_symbol("XML_SetReparseDeferralEnabled");
    looked_up = 1;
  }
  if (parser && set_deferral)
  {
    set_deferral(parser, XML_FALSE);
  }
  return parser;
}

XML_Parser XML_ParserCreate(const XML_Char* encoding)
{
  static CreateFn next = 0;
  if (!next)
  {
    next = (CreateFn)next_symbol("XML_ParserCreate");
  }
  return without_deferral(next(encoding));
}

XML_Parser XML_ParserCreateNS(const XML_Char* encoding, XML_Char separator)
{
  static CreateNSFn next = 0;
  if (!next)
  {
    next = (CreateNSFn)next_symbol("XML_ParserCreateNS");
  }
  return without_deferral(next(encoding, separator));
}

XML_Parser XML_ParserCreate_MM(const XML_Char* encoding,
  const XML_Memory_Handling_Suite* memsuite,
  const XML_Char* separator)
{
  static CreateMMFn next = 0;
  if (!next)
  {
    next = (CreateMMFn)next_symbol("XML_ParserCreate_MM");
  }
  return without_deferral(next(encoding, memsuite, separator));
}

/* A reset re-initializes the parser, deferral included. */
XML_Bool XML_ParserReset(XML_Parser parser, const XML_Char* encoding)
{
  static ResetFn next = 0;
  if (!next)
  {
    next = (ResetFn)next_symbol("XML_ParserReset");
  }
  const XML_Bool done = next(parser, encoding);
  without_deferral(parser);
  return done;
}
