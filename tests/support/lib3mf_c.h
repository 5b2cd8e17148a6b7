/* tests/support/lib3mf_c.h - the few functions of lib3mf 1.8's C interface the tests and the
 * bench use to WRITE 3MF files (an independent writer for the reader under test). lib3mf's
 * own header (NMR_DLLInterfaces.h) is C++ only, so the C declarations are repeated here with
 * the same ABI: every handle is a pointer, results are int (0: success), DWORD is unsigned,
 * a vertex is 3 floats, a triangle 3 unsigned, a transform 3 rows of 4 floats (x' = row . (x,
 * y, z, 1)). Link with -l3MF. The reading functions at the end make lib3mf the test oracle of
 * hovox's own 3MF reader (tests/io/3mf/test_mesh_read.c). */
#ifndef HOVOX_TEST_LIB3MF_C_H
#define HOVOX_TEST_LIB3MF_C_H

typedef void *l3mf;

enum { L3MF_MICRON = 0, L3MF_MM = 1, L3MF_CM = 2, L3MF_INCH = 3, L3MF_FOOT = 4, L3MF_METER = 5 };

int lib3mf_createmodel(l3mf *model);
int lib3mf_release(l3mf obj);
int lib3mf_getlasterror(l3mf obj, unsigned *code, const char **message);
int lib3mf_model_setunit(l3mf model, unsigned unit);
int lib3mf_model_addmeshobject(l3mf model, l3mf *mesh);
int lib3mf_model_addcomponentsobject(l3mf model, l3mf *components);
int lib3mf_object_setnameutf8(l3mf object, const char *name);
int lib3mf_object_settype(l3mf object, unsigned type); /* 1 model, 2 support, 3 solid support, 0 other */
int lib3mf_meshobject_setgeometry(l3mf mesh, const float *xyz, unsigned nv, const unsigned *tri, unsigned nt);
int lib3mf_componentsobject_addcomponent(l3mf components, l3mf object, const float *transform, l3mf *component);
int lib3mf_model_addbuilditem(l3mf model, l3mf object, const float *transform, l3mf *item);
int lib3mf_model_addbasematerialgroup(l3mf model, l3mf *group);
int lib3mf_basematerial_addmaterialutf8(l3mf group, const char *name, unsigned char r, unsigned char g, unsigned char b,
                                        unsigned *index);
int lib3mf_basematerial_setdisplaycolorrgba(l3mf group, unsigned index, unsigned char r, unsigned char g,
                                            unsigned char b, unsigned char a);
int lib3mf_basematerial_getresourceid(l3mf group, unsigned *id);
int lib3mf_object_createdefaultpropertyhandler(l3mf object, l3mf *handler);
int lib3mf_defaultpropertyhandler_setbasematerial(l3mf handler, unsigned group, unsigned index);
int lib3mf_defaultpropertyhandler_setcolorrgb(l3mf handler, unsigned char r, unsigned char g, unsigned char b);
int lib3mf_meshobject_createpropertyhandler(l3mf mesh, l3mf *handler);
int lib3mf_propertyhandler_setbasematerial(l3mf handler, unsigned triangle, unsigned group, unsigned index);
int lib3mf_propertyhandler_setsinglecolorrgb(l3mf handler, unsigned triangle, unsigned char r, unsigned char g,
                                             unsigned char b);
int lib3mf_model_querywriter(l3mf model, const char *kind, l3mf *writer);
int lib3mf_writer_writetofileutf8(l3mf writer, const char *path);
int lib3mf_writer_getstreamsize(l3mf writer, unsigned long long *size);
int lib3mf_writer_writetobuffer(l3mf writer, unsigned char *buffer, unsigned long long size);

/* reading (BOOL is int) */
int lib3mf_model_queryreader(l3mf model, const char *kind, l3mf *reader);
int lib3mf_reader_readfrombuffer(l3mf reader, const unsigned char *buffer, unsigned long long size);
int lib3mf_model_getunit(l3mf model, unsigned *unit);
int lib3mf_model_getbuilditems(l3mf model, l3mf *iterator);
int lib3mf_builditemiterator_movenext(l3mf iterator, int *has);
int lib3mf_builditemiterator_getcurrent(l3mf iterator, l3mf *item);
int lib3mf_builditem_getobjectresource(l3mf item, l3mf *object);
int lib3mf_builditem_hasobjecttransform(l3mf item, int *has);
int lib3mf_builditem_getobjecttransform(l3mf item, float *transform);
int lib3mf_object_gettype(l3mf object, unsigned *type);
int lib3mf_object_getnameutf8(l3mf object, char *buffer, unsigned size, unsigned *needed);
int lib3mf_object_ismeshobject(l3mf object, int *is);
int lib3mf_object_iscomponentsobject(l3mf object, int *is);
int lib3mf_meshobject_getvertexcount(l3mf mesh, unsigned *count);
int lib3mf_meshobject_gettrianglecount(l3mf mesh, unsigned *count);
int lib3mf_meshobject_getvertices(l3mf mesh, float *xyz, unsigned size, unsigned *needed);
int lib3mf_meshobject_gettriangleindices(l3mf mesh, unsigned *tri, unsigned size, unsigned *needed);
int lib3mf_componentsobject_getcomponentcount(l3mf components, unsigned *count);
int lib3mf_componentsobject_getcomponent(l3mf components, unsigned index, l3mf *component);
int lib3mf_component_getobjectresource(l3mf component, l3mf *object);
int lib3mf_component_hastransform(l3mf component, int *has);
int lib3mf_component_gettransform(l3mf component, float *transform);

#endif
