// SPDX-License-Identifier: BSD-3-Clause
// vtkSightlineMIFReader against MRtrix3-written files and VTK's own NIfTI reader.
//
// The SHData fixture (scripts/make_sh_data.py) converts one tournier07 SH NIfTI with mrconvert
// into: a .mif with the NIfTI's axes (layout +0,+1,+2,+3), a .mif.gz with the same axes but
// stored with strides -2,3,-4,1 (coefficients fastest, two axes reversed on disk), and a .mif
// with MRtrix's default realignment (axes permuted and flipped in the header). The NIfTI has
// qfac = -1, so vtkNIFTIImageReader reverses its slices; the MIF reader follows the same
// convention for a left-handed transform, so the first two files must read into the very
// same image and matrix. The realigned file has other axes: it is compared in scanner space.
#include "vtkSightlineMIFReader.h"

#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkMatrix4x4.h"
#include "vtkNIFTIImageReader.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

namespace
{
const std::string DataDir = SIGHTLINE_SH_DATA_DIR;
const std::string TempDir = SIGHTLINE_TEST_TEMP_DIR;
const std::string NiftiFile = DataDir + "/small_64D_sh_tournier07.nii.gz";
constexpr int SHCount = 45;

// Collects the ErrorEvent messages of the objects it observes (the reader reports through
// vtkErrorMacro, which invokes ErrorEvent and prints nothing while an observer handles it).
struct ErrorLog
{
  std::vector<std::string> Messages;
  vtkNew<vtkCallbackCommand> Command;
  ErrorLog()
  {
    this->Command->SetClientData(this);
    this->Command->SetCallback([](vtkObject*, unsigned long, void* client, void* call) {
      static_cast<ErrorLog*>(client)->Messages.emplace_back(
        call ? static_cast<const char*>(call) : "");
    });
  }
  void Observe(vtkObject* object) { object->AddObserver(vtkCommand::ErrorEvent, this->Command); }
  bool Contains(const std::string& fragment) const
  {
    for (const auto& message : this->Messages)
    {
      if (message.find(fragment) != std::string::npos)
      {
        return true;
      }
    }
    return false;
  }
};

vtkSmartPointer<vtkImageData> ReadNifti(vtkSmartPointer<vtkNIFTIImageReader>& reader)
{
  reader = vtkSmartPointer<vtkNIFTIImageReader>::New();
  reader->SetFileName(NiftiFile.c_str());
  reader->TimeAsVectorOn();
  reader->Update();
  return reader->GetOutput();
}

struct MifRead
{
  vtkNew<vtkSightlineMIFReader> Reader;
  ErrorLog Errors;
  vtkImageData* Output = nullptr;
  explicit MifRead(const std::string& fileName)
  {
    this->Errors.Observe(this->Reader);
    this->Reader->SetFileName(fileName.c_str());
    this->Reader->Update();
    this->Output = this->Reader->GetOutput();
  }
};

std::string ReadBytes(const std::string& path)
{
  std::ifstream stream(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>());
}

void WriteBytes(const std::string& path, const std::string& bytes)
{
  std::ofstream stream(path, std::ios::binary | std::ios::trunc);
  stream.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// A single-file MIF: the header, padded so the data start at a multiple of 16, then the data.
void WriteMif(const std::string& path, const std::string& keys, const std::string& data)
{
  std::string header = "mrtrix image\n" + keys;
  // "file: . NNNNNN\nEND\n" with a fixed-width offset keeps the arithmetic simple.
  const std::size_t fixed = header.size() + std::strlen("file: . 000000\nEND\n");
  const std::size_t offset = (fixed + 15) / 16 * 16;
  char entry[64];
  std::snprintf(entry, sizeof(entry), "file: . %06zu\nEND\n", offset);
  header += entry;
  header.resize(offset, '\0');
  WriteBytes(path, header + data);
}

double Element(vtkImageData* image, int i, int j, int k, int c)
{
  const int* dims = image->GetDimensions();
  const vtkIdType id = i + static_cast<vtkIdType>(dims[0]) * (j + static_cast<vtkIdType>(dims[1]) * k);
  return image->GetPointData()->GetScalars()->GetComponent(id, c);
}

// ---------------------------------------------------------------------------------------------
class MIFReaderMatchesNIfTI : public ::testing::TestWithParam<const char*>
{
};

TEST_P(MIFReaderMatchesNIfTI, SameVoxelsSpacingAndMatrix)
{
  vtkSmartPointer<vtkNIFTIImageReader> nifti;
  vtkSmartPointer<vtkImageData> expected = ReadNifti(nifti);
  ASSERT_EQ(expected->GetPointData()->GetScalars()->GetNumberOfComponents(), SHCount);
  // The point of the comparison: this file is left-handed, VTK reverses its slices.
  ASSERT_LT(nifti->GetQFac(), 0.0);

  MifRead mif(DataDir + "/" + GetParam());
  ASSERT_TRUE(mif.Errors.Messages.empty()) << mif.Errors.Messages.front();
  vtkImageData* image = mif.Output;
  vtkDataArray* values = image->GetPointData()->GetScalars();
  ASSERT_NE(values, nullptr);
  EXPECT_STREQ(values->GetName(), "SHCoefficients");
  EXPECT_EQ(values->GetDataType(), VTK_FLOAT);
  ASSERT_EQ(values->GetNumberOfComponents(), SHCount);
  EXPECT_STREQ(mif.Reader->GetDataTypeName(), "Float32LE");
  EXPECT_TRUE(mif.Reader->GetSlicesReversed());

  int dims[3], expectedDims[3];
  image->GetDimensions(dims);
  expected->GetDimensions(expectedDims);
  for (int a = 0; a < 3; ++a)
  {
    EXPECT_EQ(dims[a], expectedDims[a]) << "axis " << a;
    EXPECT_DOUBLE_EQ(image->GetSpacing()[a], expected->GetSpacing()[a]) << "axis " << a;
    EXPECT_DOUBLE_EQ(image->GetOrigin()[a], 0.0) << "axis " << a;
  }
  ASSERT_EQ(values->GetNumberOfTuples(), expected->GetNumberOfPoints());

  // Both readers reversed the slices, so VTK voxel (i,j,k) is the same voxel in both; the
  // float32 values are mrconvert's unchanged copies.
  vtkDataArray* reference = expected->GetPointData()->GetScalars();
  int mismatches = 0;
  double nonZero = 0;
  for (vtkIdType id = 0; id < values->GetNumberOfTuples(); ++id)
  {
    for (int c = 0; c < SHCount; ++c)
    {
      const double got = values->GetComponent(id, c);
      nonZero += got != 0.0;
      if (got != reference->GetComponent(id, c) && mismatches++ < 5)
      {
        ADD_FAILURE() << "point " << id << " component " << c << ": " << got
                      << " != " << reference->GetComponent(id, c);
      }
    }
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(nonZero, 1000) << "the comparison must cover real (non-zero) coefficients";

  vtkMatrix4x4* transform = mif.Reader->GetTransformMatrix();
  vtkMatrix4x4* qform = nifti->GetQFormMatrix();
  for (int r = 0; r < 4; ++r)
  {
    for (int c = 0; c < 4; ++c)
    {
      EXPECT_NEAR(transform->GetElement(r, c), qform->GetElement(r, c), 1e-5)
        << "element (" << r << ", " << c << ")";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(MIFReader, MIFReaderMatchesNIfTI,
  ::testing::Values("small_64D_sh_tournier07.mif", "small_64D_sh_tournier07.mif.gz"),
  [](const ::testing::TestParamInfo<const char*>& info) {
    return std::string(info.param).find(".gz") != std::string::npos ? "MifGz" : "Mif";
  });

// MRtrix's default realignment permutes and flips the axes in the header (the bytes stay
// those of the NIfTI). Every MIF voxel, carried to scanner space by GetTransformMatrix() and
// back into the NIfTI's VTK grid by the inverse QForm, must land on a voxel holding its values.
TEST(MIFReader, RealignedFileAgreesInScannerSpace)
{
  vtkSmartPointer<vtkNIFTIImageReader> nifti;
  vtkSmartPointer<vtkImageData> expected = ReadNifti(nifti);
  MifRead mif(DataDir + "/small_64D_sh_tournier07_realigned.mif");
  ASSERT_TRUE(mif.Errors.Messages.empty()) << mif.Errors.Messages.front();
  EXPECT_FALSE(mif.Reader->GetSlicesReversed()) << "MRtrix's realigned transform is a rotation";

  vtkNew<vtkMatrix4x4> toNifti;
  vtkMatrix4x4::Invert(nifti->GetQFormMatrix(), toNifti);
  vtkNew<vtkMatrix4x4> mifToNifti;
  vtkMatrix4x4::Multiply4x4(toNifti, mif.Reader->GetTransformMatrix(), mifToNifti);
  // The axes really differ (otherwise this test would repeat the one above).
  EXPECT_LT(std::fabs(mifToNifti->GetElement(0, 0)), 0.5);

  int dims[3], niftiDims[3];
  mif.Output->GetDimensions(dims);
  expected->GetDimensions(niftiDims);
  const double* spacing = mif.Output->GetSpacing();
  const double* niftiSpacing = expected->GetSpacing();
  int compared = 0, mismatches = 0;
  for (int k = 0; k < dims[2]; ++k)
  {
    for (int j = 0; j < dims[1]; ++j)
    {
      for (int i = 0; i < dims[0]; ++i)
      {
        const double p[4] = { i * spacing[0], j * spacing[1], k * spacing[2], 1.0 };
        double q[4];
        mifToNifti->MultiplyPoint(p, q);
        int index[3];
        for (int a = 0; a < 3; ++a)
        {
          const double continuous = q[a] / niftiSpacing[a];
          index[a] = static_cast<int>(std::lround(continuous));
          ASSERT_NEAR(continuous, index[a], 1e-3) << "voxel " << i << "," << j << "," << k;
          ASSERT_GE(index[a], 0);
          ASSERT_LT(index[a], niftiDims[a]);
        }
        for (int c = 0; c < SHCount; ++c)
        {
          const double got = Element(mif.Output, i, j, k, c);
          const double want = Element(expected, index[0], index[1], index[2], c);
          if (got != want && mismatches++ < 5)
          {
            ADD_FAILURE() << "MIF voxel " << i << "," << j << "," << k << " component " << c
                          << ": " << got << " != " << want;
          }
        }
        ++compared;
      }
    }
  }
  EXPECT_EQ(compared, niftiDims[0] * niftiDims[1] * niftiDims[2]);
  EXPECT_EQ(mismatches, 0);
}

// ---------------------------------------------------------------------------------------------
// Hand-made files: datatypes and byte orders MRtrix writes but the fixture does not use.

// Stores `value` as the named type, little- or big-endian.
template <typename T>
std::string Encode(double value, bool bigEndian)
{
  const T typed = static_cast<T>(value);
  char bytes[sizeof(T)];
  std::memcpy(bytes, &typed, sizeof(T));
  const std::uint16_t probe = 1;
  const bool hostLittle = *reinterpret_cast<const unsigned char*>(&probe) == 1;
  std::string out(bytes, sizeof(T));
  if (hostLittle == bigEndian)
  {
    out.assign(out.rbegin(), out.rend());
  }
  return out;
}

struct TypeCase
{
  const char* Name;
  std::string (*Encoder)(double, bool);
  bool BigEndian;
  bool Signed;
  bool Fractional;
};

class MIFReaderDataTypes : public ::testing::TestWithParam<TypeCase>
{
};

TEST_P(MIFReaderDataTypes, DecodesEveryElement)
{
  const TypeCase& type = GetParam();
  // 3 x 2 x 2 x 2 in MRtrix's default order; element e holds a value that depends on e, is
  // exact in every type, and uses the sign and fraction where the type has them.
  const int nx = 3, ny = 2, nz = 2, nc = 2;
  auto valueOf = [&](int e) {
    double v = e + 1;
    if (type.Signed)
    {
      v = (e % 2 ? -1 : 1) * v * 3;
    }
    return type.Fractional ? v + 0.25 : v;
  };
  std::string data;
  for (int e = 0; e < nx * ny * nz * nc; ++e)
  {
    data += type.Encoder(valueOf(e), type.BigEndian);
  }
  const std::string path = TempDir + "/mif_datatype_" + type.Name + ".mif";
  WriteMif(path,
    std::string("dim: 3,2,2,2\nvox: 1.5,2,2.5,1\nlayout: +0,+1,+2,+3\ndatatype: ") + type.Name +
      "\ntransform: 1,0,0,0\ntransform: 0,1,0,0\ntransform: 0,0,1,0\n",
    data);

  MifRead mif(path);
  ASSERT_TRUE(mif.Errors.Messages.empty()) << mif.Errors.Messages.front();
  int dims[3];
  mif.Output->GetDimensions(dims);
  ASSERT_EQ(dims[0], nx);
  ASSERT_EQ(dims[1], ny);
  ASSERT_EQ(dims[2], nz);
  ASSERT_EQ(mif.Output->GetPointData()->GetScalars()->GetNumberOfComponents(), nc);
  EXPECT_DOUBLE_EQ(mif.Output->GetSpacing()[0], 1.5);
  EXPECT_DOUBLE_EQ(mif.Output->GetSpacing()[2], 2.5);
  for (int c = 0; c < nc; ++c)
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
        {
          const int e = i + nx * (j + ny * (k + nz * c));
          EXPECT_EQ(Element(mif.Output, i, j, k, c), valueOf(e))
            << type.Name << " element " << e;
        }
}

std::string EncodeI8(double v, bool be) { return Encode<std::int8_t>(v, be); }
std::string EncodeU8(double v, bool be) { return Encode<std::uint8_t>(v, be); }
std::string EncodeI16(double v, bool be) { return Encode<std::int16_t>(v, be); }
std::string EncodeU16(double v, bool be) { return Encode<std::uint16_t>(v, be); }
std::string EncodeI32(double v, bool be) { return Encode<std::int32_t>(v, be); }
std::string EncodeF32(double v, bool be) { return Encode<float>(v, be); }
std::string EncodeF64(double v, bool be) { return Encode<double>(v, be); }

INSTANTIATE_TEST_SUITE_P(MIFReader, MIFReaderDataTypes,
  ::testing::Values(TypeCase{ "Int8", EncodeI8, false, true, false },
    TypeCase{ "UInt8", EncodeU8, false, false, false },
    TypeCase{ "Int16LE", EncodeI16, false, true, false },
    TypeCase{ "Int16BE", EncodeI16, true, true, false },
    TypeCase{ "UInt16BE", EncodeU16, true, false, false },
    TypeCase{ "Int32BE", EncodeI32, true, true, false },
    TypeCase{ "Float32LE", EncodeF32, false, true, true },
    TypeCase{ "Float32BE", EncodeF32, true, true, true },
    TypeCase{ "Float64LE", EncodeF64, false, true, true },
    TypeCase{ "Float64BE", EncodeF64, true, true, true }),
  [](const ::testing::TestParamInfo<TypeCase>& info) { return std::string(info.param.Name); });

// A layout worked out by hand: dim 2,3,1 with layout -1,+0,+2 stores axis 1 fastest and axis 0
// second, reversed. Disk element e is therefore axis-1 index e % 3 and axis-0 index 1 - e / 3.
// The scaling entry (offset, multiplier) applies on top.
TEST(MIFReader, HandWorkedLayoutAndScaling)
{
  std::string data;
  for (int e = 0; e < 6; ++e)
  {
    data += Encode<std::int16_t>(e, false);
  }
  const std::string path = TempDir + "/mif_layout.mif";
  WriteMif(path, "dim: 2,3,1\nvox: 1,1,1\nlayout: -1,+0,+2\ndatatype: Int16LE\n"
                 "scaling: 10,0.5\n",
    data);
  MifRead mif(path);
  ASSERT_TRUE(mif.Errors.Messages.empty()) << mif.Errors.Messages.front();
  ASSERT_EQ(mif.Output->GetPointData()->GetScalars()->GetNumberOfComponents(), 1);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 3; ++j)
    {
      const int e = (1 - i) * 3 + j;
      EXPECT_EQ(Element(mif.Output, i, j, 0, 0), 10 + 0.5 * e) << "voxel " << i << "," << j;
    }
  // No transform entry: identity.
  EXPECT_TRUE(mif.Reader->GetTransformMatrix()->IsIdentity());
}

// A left-handed transform written by hand: slice k of the output is the file's slice nz-1-k and
// the matrix becomes a rotation with its translation at the file's last slice.
TEST(MIFReader, LeftHandedTransformReversesSlices)
{
  std::string data;
  for (int e = 0; e < 2 * 1 * 3; ++e)
  {
    data += Encode<float>(e, false);
  }
  const std::string path = TempDir + "/mif_left_handed.mif";
  WriteMif(path, "dim: 2,1,3\nvox: 1,1,2\nlayout: +0,+1,+2\ndatatype: Float32LE\n"
                 "transform: 0,1,0,5\ntransform: 1,0,0,6\ntransform: 0,0,1,7\n",
    data);
  MifRead mif(path);
  ASSERT_TRUE(mif.Errors.Messages.empty()) << mif.Errors.Messages.front();
  EXPECT_TRUE(mif.Reader->GetSlicesReversed());
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 2; ++i)
    {
      EXPECT_EQ(Element(mif.Output, i, 0, k, 0), i + 2 * (2 - k)) << "voxel " << i << ",0," << k;
    }
  vtkMatrix4x4* m = mif.Reader->GetTransformMatrix();
  EXPECT_DOUBLE_EQ(m->GetElement(2, 2), -1.0);
  EXPECT_DOUBLE_EQ(m->Determinant(), 1.0);
  // File voxel (0,0,2), i.e. output voxel (0,0,0), sits at scanner (5, 6, 7 + 2*2).
  const double origin[4] = { 0, 0, 0, 1 };
  double scanner[4];
  m->MultiplyPoint(origin, scanner);
  EXPECT_DOUBLE_EQ(scanner[0], 5.0);
  EXPECT_DOUBLE_EQ(scanner[1], 6.0);
  EXPECT_DOUBLE_EQ(scanner[2], 11.0);
}

// ---------------------------------------------------------------------------------------------
// Bad input: an error through vtkErrorMacro, an empty output, no crash.
void ExpectError(const std::string& path, const std::string& fragment)
{
  MifRead mif(path);
  EXPECT_TRUE(mif.Errors.Contains(fragment))
    << "expected an error containing \"" << fragment << "\", got "
    << (mif.Errors.Messages.empty() ? std::string("none") : mif.Errors.Messages.front());
  EXPECT_EQ(mif.Output->GetNumberOfPoints(), 0);
}

TEST(MIFReaderBadInput, MissingFile)
{
  ExpectError(TempDir + "/no_such_file.mif", "Cannot open");
}

TEST(MIFReaderBadInput, WrongMagic)
{
  const std::string path = TempDir + "/mif_wrong_magic.mif";
  WriteBytes(path, "mrtrix imagf\ndim: 1,1,1\nvox: 1,1,1\nlayout: +0,+1,+2\n"
                   "datatype: UInt8\nfile: . 100\nEND\n");
  ExpectError(path, "is not an MRtrix image");
  EXPECT_EQ(vtkSightlineMIFReader::CanReadFile(path.c_str()), 0);
  EXPECT_EQ(vtkSightlineMIFReader::CanReadFile((DataDir + "/small_64D_sh_tournier07.mif.gz").c_str()), 1);
}

TEST(MIFReaderBadInput, TruncatedCopy)
{
  const std::string whole = ReadBytes(DataDir + "/small_64D_sh_tournier07.mif");
  ASSERT_GT(whole.size(), 100000u);
  const std::string path = TempDir + "/mif_truncated.mif";
  WriteBytes(path, whole.substr(0, whole.size() - 1000));
  ExpectError(path, "is truncated");
}

TEST(MIFReaderBadInput, TruncatedGzipCopy)
{
  const std::string whole = ReadBytes(DataDir + "/small_64D_sh_tournier07.mif.gz");
  ASSERT_GT(whole.size(), 10000u);
  const std::string path = TempDir + "/mif_truncated.mif.gz";
  WriteBytes(path, whole.substr(0, whole.size() / 2));
  ExpectError(path, "is truncated");
}

TEST(MIFReaderBadInput, UnsupportedDataType)
{
  const std::string path = TempDir + "/mif_cfloat.mif";
  WriteMif(path, "dim: 1,1,1\nvox: 1,1,1\nlayout: +0,+1,+2\ndatatype: CFloat32LE\n",
    std::string(8, '\0'));
  ExpectError(path, "unsupported datatype 'CFloat32LE'");
}

TEST(MIFReaderBadInput, FiveAxes)
{
  const std::string path = TempDir + "/mif_5d.mif";
  WriteMif(path, "dim: 1,1,1,2,2\nvox: 1,1,1,1,1\nlayout: +0,+1,+2,+3,+4\ndatatype: UInt8\n",
    std::string(4, '\0'));
  ExpectError(path, "only images of up to 4 axes are supported");
}
} // namespace
